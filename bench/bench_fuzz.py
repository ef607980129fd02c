"""Fuzzing every input kind through the real ``lbw`` entry point (issue #15).

Cases are split evenly over the kinds of bench/fuzzcases.py (rule folders,
scenarios, actions.json, plan.json, traces); case i of kind K draws its
mutations from ``random.Random(f"{seed}:{K}:{i}")``, so any case can be rerun
alone. Per kind it prints the cases, the exit-code histogram, tracebacks,
internal errors (exit 3), rejections over one line, cases with leftover files,
hung cases and the time per case, then the failing cases.

    .venv/bin/python -m bench fuzz                          # 2,000 cases, seed 1
    .venv/bin/python -m bench fuzz --count 10000 --jobs 2
    .venv/bin/python -m bench fuzz --kinds plan,scenario --count 60 --simulate  # in full
    .venv/bin/python -m bench fuzz --kinds scenario --seed 1 --only 123   # one case
"""

from __future__ import annotations

import argparse
import os
import random
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from bench.fuzzcases import KINDS, run_case

SHOWN_FAILURES = 10  # failing cases listed per kind


def _case(job: tuple[str, int, int, bool]) -> dict[str, Any]:
    """Run one case in a worker; return what the report needs."""
    kind, seed, index, simulate = job
    outcome = run_case(kind, random.Random(f"{seed}:{kind}:{index}"), simulate)
    runs = outcome.runs
    return {
        "kind": kind, "index": index, "mutation": outcome.mutation, "code": outcome.code,
        "ok": outcome.ok, "hung": outcome.hung, "leftovers": outcome.leftovers,
        "traceback": any(r.traceback for r in runs), "internal": any(r.internal for r in runs),
        "multiline": any(r.multiline for r in runs),
        "seconds": sum(r.seconds for r in runs),
        "message": (runs[-1].escaped or runs[-1].stderr.strip())[:300] if runs else "",
    }


def _table(results: list[dict[str, Any]], kinds: tuple[str, ...]) -> dict[str, Any]:
    """Figures per kind."""
    figures: dict[str, Any] = {}
    for kind in kinds:
        rows = [r for r in results if r["kind"] == kind]
        n = max(len(rows), 1)
        figures[kind] = {
            "cases": len(rows),
            "exit_codes": dict(sorted(Counter(r["code"] for r in rows).items())),
            "tracebacks": sum(r["traceback"] for r in rows),
            "internal_errors": sum(r["internal"] for r in rows),
            "messages_over_one_line": sum(r["multiline"] for r in rows),
            "leftover_files": sum(bool(r["leftovers"]) for r in rows),
            "hung": sum(r["hung"] for r in rows),
            "seconds_per_case": round(sum(r["seconds"] for r in rows) / n, 3),
            "failures": [f"{r['index']} {r['mutation']}: {r['message']}"
                         for r in rows if not r["ok"]][:SHOWN_FAILURES],
        }
    return figures


def _print(figures: dict[str, Any], seed: int, wall: float) -> None:
    """The table, then the failing cases."""
    head = ("kind", "cases", "exit codes", "tracebacks", "internal", "over 1 line",
            "leftovers", "hung", "s/case")
    print(f"{head[0]:<9}{head[1]:>7}  {head[2]:<28}" + "".join(f"{h:>12}" for h in head[3:]))
    for kind, f in figures.items():
        codes = " ".join(f"{c}:{n}" for c, n in f["exit_codes"].items())
        print(f"{kind:<9}{f['cases']:>7}  {codes:<28}" + "".join(
            f"{f[k]:>12}" for k in ("tracebacks", "internal_errors", "messages_over_one_line",
                                    "leftover_files", "hung", "seconds_per_case")))
    print(f"seed {seed}, {wall:.0f} s wall")
    for kind, f in figures.items():
        for line in f["failures"]:
            print(f"FAILED {kind} case {line}")


def main(argv: list[str]) -> dict[str, Any]:
    """Run the fuzz campaign; return the figures per kind."""
    parser = argparse.ArgumentParser(prog="python -m bench fuzz", description=__doc__.split(
        "\n")[0])
    parser.add_argument("--count", type=int, default=2000, help="cases in all (2000)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--kinds", default=",".join(KINDS), help="comma-separated kinds")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--simulate", action="store_true",
                        help="accepted scenarios are watched and plans executed in full "
                             "(slow: seconds to a minute a case)")
    parser.add_argument("--only", type=int, default=None, help="run only case number ONLY")
    args = parser.parse_args(argv)
    kinds = tuple(k for k in args.kinds.split(",") if k)
    per_kind = max(1, args.count // len(kinds))
    indices = [args.only] if args.only is not None else list(range(per_kind))
    jobs = [(kind, args.seed, i, args.simulate) for i in indices for kind in kinds]
    start = time.perf_counter()
    if args.jobs > 1 and len(jobs) > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            results = list(pool.map(_case, jobs, chunksize=8))
    else:
        results = [_case(job) for job in jobs]
    figures = _table(results, kinds)
    _print(figures, args.seed, time.perf_counter() - start)
    return {"seed": args.seed, "count": len(jobs), "kinds": figures}


if __name__ == "__main__":
    main(sys.argv[1:])
