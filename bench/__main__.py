"""Run every bench/bench_*.py (or the ones named) and save their figures as JSON."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv: list[str]) -> int:
    """Run the named benchmarks (default: all) and write bench/results/NAME.json.

    Options after the names go to each named benchmark's ``main``
    (``python -m bench fuzz --count 10000``).
    """
    first_option = next((i for i, a in enumerate(argv) if a.startswith("-")), len(argv))
    names, options = argv[:first_option], argv[first_option:]
    names = names or sorted(p.stem.removeprefix("bench_") for p in HERE.glob("bench_*.py"))
    results = HERE / "results"
    results.mkdir(exist_ok=True)
    for name in names:
        module = importlib.import_module(f"bench.bench_{name}")
        print(f"== bench {name}", flush=True)
        figures = module.main(list(options))
        (results / f"{name}.json").write_text(json.dumps(figures, indent=1) + "\n")
        print(f"   figures written to bench/results/{name}.json", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
