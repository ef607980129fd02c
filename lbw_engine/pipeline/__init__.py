"""The pipeline: see, understand and do, wired to the simulated workspace.

``watch`` (seeing, pipeline.watch), ``execute_plan`` (doing, pipeline.execute)
and ``run`` (the three phases in order, with the verdict and the first phase
that failed, pipeline.run). The command line, the benchmark and the report
use these; this is the one place besides the command line where lbw_engine
meets perception (import-linter contracts in pyproject.toml).
"""
