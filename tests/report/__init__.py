"""Tests of the pictures of a run: videos, plan drawings, report.html (issue #7, #14)."""
