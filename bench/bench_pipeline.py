"""The whole pipeline on generated scenarios: `lbw bench` as a benchmark module.

    .venv/bin/python -m bench pipeline            # 12 scenarios, seed 1, all cores
    .venv/bin/python -m bench.bench_pipeline 100 1

Per noise level: exact-sequence rate, edit accuracy, segmentation timing error,
plan correctness, execution success, real-time factors, pixels read per frame
(lbw_engine/cli/bench.py). docs/benchmarks.md records the figures.
"""

from __future__ import annotations

import os
import sys
from typing import Any

from lbw_engine.cli.bench import bench
from lbw_engine.report.metrics import format_table


def main(argv: list[str]) -> dict[str, Any]:
    """Run ``count`` (default 12) scenarios from ``seed`` (default 1); print the table."""
    count = int(argv[0]) if argv else 12
    seed = int(argv[1]) if len(argv) > 1 else 1
    doc = bench(count, seed, os.cpu_count() or 1)
    print(format_table(doc["summary"]))
    for f in doc["failures"]:
        print(f"  seed {f['seed']} ({f['level']}, {'+'.join(f['structures'])}): "
              f"{'; '.join(f['what'])}")
    return {k: doc[k] for k in ("count", "seed", "runner", "wall_seconds", "summary", "failures")}


if __name__ == "__main__":
    main(sys.argv[1:])
