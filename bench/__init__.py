"""Benchmarks: ``python -m bench [NAME ...]`` (see docs/architecture.md)."""
