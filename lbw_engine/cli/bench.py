"""``lbw bench [--count N] [--seed S] [--out FILE] [--jobs J]``: measure the whole pipeline.

Generates N random scenarios (``perception.world.generator``; scenario i has seed
S*1000+i and noise level nominal, 2x, 4x in turn), runs watch → analyze →
execute on each in a process pool, and reports per noise level: exact-sequence
rate, edit-distance accuracy, segmentation timing error (median, 95th
percentile), plan correctness (the plan root's SC+ support relations equal the
true final relations of the moved objects), execution success, real-time
factors and pixels read per frame. A table on screen, every figure and every
failing case (seed, structures, what went wrong) in the JSON file.

The ground truth is consulted only after each phase, for scoring.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import math
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.outputs import atomic_write_text, to_json
from lbw_engine.report.metrics import (
    compare_sequence,
    format_table,
    plan_final_relations,
    summarize,
    support_facts,
)

HELP = "benchmark watch → analyze → execute on seeded random scenarios at three noise levels"
LEVELS = ("nominal", "2x", "4x")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """--count, --seed, --out, --jobs, --rules."""
    parser.add_argument("--count", type=int, default=30, help="number of scenarios (30)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the scenario set (1)")
    parser.add_argument("--out", metavar="FILE", default="bench-pipeline.json",
                        help="JSON results file (bench-pipeline.json)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="worker processes (default: all cores)")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")
    parser.add_argument("--scenarios", metavar="DIR",
                        help="also write each generated scenario as DIR/gen-SEED-LEVEL.yaml "
                             "(to rerun a failing case with lbw run)")


def tasks(count: int, seed: int) -> list[tuple[int, str]]:
    """(generator seed, noise level) of each scenario of the set."""
    return [(seed * 1000 + i, LEVELS[i % len(LEVELS)]) for i in range(count)]


_RULES: dict[Any, tuple] = {}


def _rules(rules_dir: str | None) -> tuple:
    """Recognition, analysis and command rules, loaded once per worker process."""
    if rules_dir not in _RULES:
        from lbw_engine.rules import load_rules

        rules = load_rules(rules_dir)
        _RULES[rules_dir] = (rules, rules.analysis, rules.commands)
    return _RULES[rules_dir]


def teach_rename(actions: dict[str, Any], scenario: Any) -> dict[str, str]:
    """Recognized object name -> the teach object of that shape nearest its measured x, y."""
    out = {}
    for name, obj in actions.get("objects", {}).items():
        same = [(n, o) for n, o in scenario.teach.objects.items() if o.shape == obj["shape"]]
        if name in scenario.teach.objects or not same:
            continue
        x, y = obj["position"][:2]
        out[name] = min(same, key=lambda no: math.dist((x, y), no[1].center[:2]))[0]
    return out


def true_final(scenario: Any, roles: Any) -> set:
    """(object, supports) after the demonstration, for every object the hand moved."""
    moved = {s.obj for s in scenario.demonstration if s.kind == "pick"}
    facts = support_facts(scenario.states[-1].relations(roles), roles.support)
    return {f for f in facts if f[0] in moved}


def run_one(task: tuple[int, str, str | None]) -> dict[str, Any]:
    """Generate, watch, analyze, execute and score one scenario (runs in a worker)."""
    seed, level, rules_dir = task
    from perception.world.generator import generate

    gen = generate(seed, level)
    rec: dict[str, Any] = {"seed": seed, "level": level, "structures": list(gen.structures),
                           "touches": gen.touches, "distractors": gen.distractors}
    try:
        _score(rec, gen.scenario(), rules_dir)
    except Exception as exc:  # a crash is a finding of the benchmark, not the end of it
        rec["error"] = f"{type(exc).__name__}: {exc}"
        rec["traceback"] = traceback.format_exc(limit=-8)  # the innermost frames
    return rec


def _score(rec: dict[str, Any], sc: Any, rules_dir: str | None) -> None:
    """Run the phases on ``sc`` and fill ``rec`` with the figures."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.pipeline.watch import watch
    from lbw_engine.see.actions import to_actions
    from lbw_engine.understand import RelationTable, analyze, parse_actions
    from perception.world.demonstrator import Demonstration
    from perception.world.groundtruth import ground_truth

    rules, arules, crules = _rules(rules_dir)
    demo = Demonstration(sc)
    truth = [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
             for t in ground_truth(sc, rules, demo)]
    rec["demo_seconds"] = demo.duration
    clock = start = time.perf_counter()
    recognizer, hand = watch(sc, rules)
    actions = to_actions(recognizer)
    rec["watch_seconds"] = time.perf_counter() - clock
    rec["pixels_per_frame"] = sum(hand.sight.pixels) / max(1, len(hand.sight.pixels))
    rec.update(compare_sequence(truth, actions["operations"]))
    rec["plan_correct"] = rec["execution_success"] = False
    clock = time.perf_counter()
    try:
        seq = parse_actions(actions, RelationTable(arules.tolerance), file="actions.json")
        plan = analyze(seq, arules).plan
    except InputError as exc:
        rec["failure"] = f"analysis: {exc}"
    else:
        rec["plan_correct"] = plan_final_relations(
            plan, rules.roles.support, teach_rename(actions, sc)) == true_final(sc, rules.roles)
        rec["analyze_seconds"] = time.perf_counter() - clock
        clock = time.perf_counter()
        result = execute_plan(planmod.parse(plan, file="plan.json"), sc, rules)
        rec["execute_seconds"] = time.perf_counter() - clock
        rec["execution_success"] = bool(result.success)
        if not result.success:
            rec["failure"] = f"execution: {result.message}"
    rec["total_seconds"] = time.perf_counter() - start


def _progress(done: int, total: int, started: float, exact: int) -> None:
    """One self-overwriting progress line on stderr."""
    width = 30
    filled = round(width * done / max(1, total))
    el = time.perf_counter() - started
    sys.stderr.write(f"\rlbw bench: [{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
                     f"{el // 60:.0f}m{el % 60:02.0f}s, exact so far {exact}/{done}  ")
    sys.stderr.flush()


def bench(count: int, seed: int, jobs: int, rules_dir: str | None = None) -> dict[str, Any]:
    """Run the benchmark; returns the JSON document (summary, failures, per-scenario records)."""
    work = [(s, level, rules_dir) for s, level in tasks(count, seed)]
    started = time.perf_counter()
    records: list[dict[str, Any]] = []
    _progress(0, len(work), started, 0)
    if jobs <= 1:
        results = map(run_one, work)
        for r in results:
            records.append(r)
            _progress(len(records), len(work), started, sum(x.get("exact", 0) for x in records))
    else:
        with cf.ProcessPoolExecutor(max_workers=jobs) as pool:
            for fut in cf.as_completed([pool.submit(run_one, w) for w in work]):
                records.append(fut.result())
                _progress(len(records), len(work), started,
                          sum(x.get("exact", 0) for x in records))
    sys.stderr.write("\n")
    records.sort(key=lambda r: r["seed"])
    return {"count": count, "seed": seed, "jobs": jobs,
            "wall_seconds": round(time.perf_counter() - started, 1),
            "summary": summarize(records, LEVELS), "failures": failures(records),
            "scenarios": records}


def failures(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Every scenario that was not recognized exactly, not planned right or not executed."""
    out = []
    for r in records:
        what = []
        if "exact" in r and not r["exact"]:
            what.append(f"sequence {r['difference']}")
        if "error" in r:
            what.append(f"crashed: {r['error']}")
        else:
            if r.get("failure"):
                what.append(r["failure"])
            elif not r["plan_correct"]:
                what.append("plan's final relations differ from the true ones")
        if what:
            out.append({"seed": r["seed"], "level": r["level"], "structures": r["structures"],
                        "touches": r["touches"], "what": what})
    return out


def run(args: argparse.Namespace) -> int:
    """Run, print the table and the failing cases, write the JSON file."""
    if args.count < 1 or args.jobs < 1:
        raise InputError("--count and --jobs must be at least 1", where="arguments")
    if args.scenarios:
        from perception.world.generator import generate

        folder = Path(args.scenarios)
        for seed, level in tasks(args.count, args.seed):
            atomic_write_text(folder / f"gen-{seed}-{level}.yaml", generate(seed, level).text)
    doc = bench(args.count, args.seed, args.jobs, args.rules)
    doc["command"] = f"lbw bench --count {args.count} --seed {args.seed} --jobs {args.jobs}"
    atomic_write_text(args.out, to_json(doc))
    print(format_table(doc["summary"]))
    print(f"{doc['count']} scenarios in {doc['wall_seconds']:.0f} s on {doc['jobs']} "
          f"process(es); {len(doc['failures'])} failing case(s):")
    for f in doc["failures"]:
        print(f"  seed {f['seed']} ({f['level']}, {'+'.join(f['structures'])}, "
              f"{f['touches']} touch(es)): {'; '.join(f['what'])}")
    print(f"figures and per-scenario records: {args.out}")
    return 0
