"""``lbw bench``: measure the whole pipeline on seeded random scenarios.

Generates N random scenarios (``perception.world.generator``; scenario i has seed
S*1000+i, noise level nominal, 2x, 4x in turn and, three by three, each family of
``--families`` in turn: ``generator.family_of``), runs watch → analyze →
execute on each and reports per noise level: exact-sequence rate (raw, and after
recognition repair, Sec. IX-C2: analysis reads the repaired sequence),
edit-distance accuracy, segmentation timing error (median, 95th percentile),
plan correctness (the plan root's SC+ support relations equal the true final
relations of the moved objects), execution success, real-time factors and pixels
read per frame. The four rates come with their 95% Wilson intervals, per level;
exact, plan and exec also per family (``lbw_engine.report.families``).

Where the scenarios run (this process, ``--jobs N`` processes or a Dask cluster
with ``--cluster``) is ``lbw_engine/cli/cluster.py``; it changes nothing in the
records but their timings. Two files: ``--out FILE`` (the summary, the failing
cases, the command) and ``--records FILE`` (JSON lines, one record per scenario,
sorted by seed: everything but the ``*_seconds`` timings is reproducible from
the seed and the rules). While it runs, finished records are appended to
``FILE.partial`` (in the order they finish), which is removed at the end;
``--resume`` keeps the records of a stopped run's partial file and runs the rest.

The ground truth is consulted only after each phase, for scoring.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import contextlib
import json
import math
import os
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from lbw_engine.cli.benchscore import (  # noqa: F401 (failures, first_failure re-exported)
    failures,
    first_failure,
    place_errors,
    target_difference,
    true_aligns,
    true_final,
)
from lbw_engine.cli.benchset import LEVELS, parse_families, tasks  # noqa: F401 (re-exported)
from lbw_engine.cli.cluster import executor, local_workers
from lbw_engine.errors import InputError
from lbw_engine.outputs import OutputDir, atomic_write_text, to_json
from lbw_engine.report.families import format_families, summarize_families
from lbw_engine.report.metrics import (
    compare_sequence,
    fine_relations,
    format_table,
    plan_final_relations,
    plan_fine_pairs,
    summarize,
)

HELP = "benchmark watch → analyze → execute on seeded random scenarios at three noise levels"
EXIT_CODES = ("0 the benchmark ran (failing scenarios are findings, not errors: the "
              "figures count them); 2 bad input (one line: place, what is wrong), also when "
              "--cluster cannot be used; 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """--count, --seed, --out, --records, --jobs, --cluster, --rules, --scenarios."""
    parser.add_argument("--count", type=int, metavar="N", default=30,
                        help="number of scenarios (30)")
    parser.add_argument("--seed", type=int, metavar="N", default=1,
                        help="seed of the scenario set (1)")
    parser.add_argument("--out", metavar="FILE", default="bench-pipeline.json",
                        help="summary JSON file (bench-pipeline.json)")
    parser.add_argument("--records", metavar="FILE",
                        help="per-scenario records, JSON lines (default: FILE of --out "
                             "with the suffix .jsonl)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--jobs", type=int, metavar="N",
                       help="worker processes on this machine (default: all cores)")
    where.add_argument("--cluster", metavar="ADDRESS",
                       help="run on a Dask cluster: a scheduler's tcp://HOST:PORT, or local:N "
                            "for a local cluster of N workers (needs lbw[cluster])")
    parser.add_argument("--resume", action="store_true",
                        help="keep the records that a stopped run of the same command left in "
                             "the records FILE.partial, and run only the other scenarios")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")
    parser.add_argument("--families", metavar="NAMES",
                        help="comma-separated scenario families to draw from, in turn "
                             "(default: all, perception.world.generator.FAMILIES; "
                             "with --faults: classic)")
    parser.add_argument("--faults", action="store_true",
                        help="execute each learned plan without and with injected faults "
                             "(drop, displace, remove; issue #13) and report detection, "
                             "repair and the cameras' agreement with the ground truth")
    parser.add_argument("--scenarios", metavar="DIR",
                        help="also write each generated scenario as DIR/gen-SEED-LEVEL.yaml "
                             "(to rerun a failing case with lbw run)")


_RULES: dict[Any, tuple] = {}


def _rules(rules_dir: str | None) -> tuple:
    """Recognition, analysis and command rules, loaded once per worker process."""
    if rules_dir not in _RULES:
        from lbw_engine.rules import load_rules

        rules = load_rules(rules_dir)
        _RULES[rules_dir] = (rules, rules.analysis, rules.commands)
    return _RULES[rules_dir]


def teach_rename(actions: dict[str, Any], scenario: Any) -> dict[str, str]:
    """Recognized object name -> the teach object of that shape nearest its measured centre
    (x, y, z: stacked blocks of one shape share x and y)."""
    out = {}
    for name, obj in actions.get("objects", {}).items():
        same = [(n, o) for n, o in scenario.teach.objects.items() if o.shape == obj["shape"]]
        if name in scenario.teach.objects or not same:
            continue
        at = obj["position"]
        out[name] = min(same, key=lambda no: math.dist(at, no[1].center[:len(at)]))[0]
    return out


def run_one(task: tuple[int, str, str, str | None]) -> dict[str, Any]:
    """Generate, watch, analyze, execute and score one scenario (runs in a worker)."""
    seed, level, family, rules_dir = task
    from perception.world.generator import generate

    gen = generate(seed, level, family=family)
    rec: dict[str, Any] = {"seed": seed, "level": level, "family": family,
                           "structures": list(gen.structures),
                           "touches": gen.touches, "distractors": gen.distractors}
    try:
        _score(rec, gen.scenario(), rules_dir)
    except Exception as exc:  # a crash is a finding of the benchmark, not the end of it
        rec["error"] = f"{type(exc).__name__}: {exc}"
        rec["traceback"] = traceback.format_exc(limit=-8)  # the innermost frames
    return rec


def _score(rec: dict[str, Any], sc: Any, rules_dir: str | None) -> None:
    """Run the pipeline on ``sc`` as ``lbw run`` does (lbw_engine.pipeline.run) and fill
    ``rec`` with the figures; the ground truth is read only to score."""
    from lbw_engine.pipeline.run import foreign_objects, run
    from lbw_engine.pipeline.watch import watch
    from perception.world.demonstrator import Demonstration
    from perception.world.groundtruth import ground_truth

    rules, _, _ = _rules(rules_dir)
    demo = Demonstration(sc)
    true_ops = ground_truth(sc, rules, demo)
    truth = [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
             for t in true_ops]
    rec["demo_seconds"] = demo.duration
    seen: dict[str, Any] = {}

    def watcher(scenario: Any, rules_: Any, fps: float) -> Any:
        recognizer, seen["hand"] = watch(scenario, rules_, fps=fps)
        return recognizer

    start = time.perf_counter()
    result = run(sc, rules_dir, watcher=watcher, rules=rules)
    rec["watch_seconds"] = result.seconds["watch"]
    sight = seen["hand"].sight.pixels
    rec["pixels_per_frame"] = sum(sight) / max(1, len(sight))
    rec.update(compare_sequence(truth, result.raw["operations"]))
    rec["place_errors_mm"] = place_errors(sc, rules.roles, true_ops, result.raw["operations"])
    rec["repairs"] = result.recognition["repair"]["repairs"]
    rec["exact_repaired"] = compare_sequence(truth, result.actions["operations"])["exact"]
    # every operation acting on the objects it really acted on (actions.json ``target``)
    rec["targets_exact"] = False
    if rec["exact"]:
        other = target_difference(true_ops, result.raw["operations"],
                                  teach_rename(result.raw, sc))
        rec["targets_exact"] = other is None
        if other is not None:
            rec["target_difference"] = other
    rec["plan_correct"] = rec["execution_success"] = False
    wrong = foreign_objects(sc, result.actions)
    if result.plan is not None:
        rec["analyze_seconds"] = result.seconds["analyze"]
        rename = teach_rename(result.actions, sc)
        # the supports, and the aligns: a lost ALIGN leaves every support right
        must, may = true_aligns(sc, rules)
        rec["aligns_correct"] = must <= plan_fine_pairs(
            result.plan, fine_relations(rules), rename) <= may
        rec["plan_correct"] = rec["aligns_correct"] and plan_final_relations(
            result.plan, rules.roles.support, rename) == true_final(sc, rules.roles)
    if result.execution is not None and not wrong:
        rec["execute_seconds"] = result.seconds["execute"]
        rec["execution_success"] = bool(result.execution.success)
        checks = result.execution.report.get("verification")
        if isinstance(checks, dict) and result.execution.report.get("stage") == "verification":
            # the cameras' verdict against the simulator's, on a finished run
            rec["verdicts_agree"] = checks["cameras"] == checks["ground_truth"]
        # no fault is injected here: every detection is the monitor's false alarm, or a
        # real slip of the robot's (issue #13: none on fault-free runs)
        rec["monitor_detections"] = len(
            (result.execution.report.get("monitor") or {}).get("detections") or [])
    failure = first_failure(result.phases, wrong)
    if failure is not None:
        rec["failure"] = failure
    rec["total_seconds"] = time.perf_counter() - start


def _progress(done: int, total: int, started: float, exact: int) -> None:
    """One self-overwriting progress line on stderr."""
    width = 30
    filled = round(width * done / max(1, total))
    el = time.perf_counter() - started
    sys.stderr.write(f"\rlbw bench: [{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
                     f"{el // 60:.0f}m{el % 60:02.0f}s, exact so far {exact}/{done}  ")
    sys.stderr.flush()


TIMINGS = ("watch_seconds", "analyze_seconds", "execute_seconds", "total_seconds")


def reproducible(record: dict[str, Any]) -> dict[str, Any]:
    """A record without its wall-clock timings: what any rerun of its seed must give."""
    return {k: v for k, v in record.items() if k not in TIMINGS}


def lost(task: tuple[int, str, str, str | None], exc: BaseException) -> dict[str, Any]:
    """The record of a scenario whose worker died (the task itself catches its own errors)."""
    seed, level, family, _ = task
    return {"seed": seed, "level": level, "family": family, "structures": [], "touches": 0,
            "distractors": 0,
            "error": f"worker lost: {type(exc).__name__}: {exc}"}


def run_all(work: list[tuple[int, str, str, str | None]], pool: cf.Executor | None,
            partial: Path | None = None, kept: Sequence[dict[str, Any]] = (),
            ) -> list[dict[str, Any]]:
    """Run every task here (``pool`` None) or on ``pool``; with ``kept``, the records
    sorted by seed.

    Each record is also appended to ``partial`` as it arrives (after ``kept``), so a
    long run that is stopped keeps the scenarios it finished (the caller removes the
    file at the end).
    """
    started = time.perf_counter()
    records: list[dict[str, Any]] = list(kept)
    total = len(work) + len(kept)
    with contextlib.ExitStack() as stack:
        sink = stack.enter_context(partial.open("w", encoding="utf-8")) if partial else None
        if sink:
            sink.write(records_text(records))

        def done(rec: dict[str, Any]) -> None:
            records.append(rec)
            if sink:
                sink.write(records_text([rec]))
                sink.flush()
            _progress(len(records), total, started, sum(x.get("exact", 0) for x in records))

        _progress(len(records), total, started, sum(x.get("exact", 0) for x in records))
        if pool is None:
            for w in work:
                done(run_one(w))
        else:
            futures = {pool.submit(run_one, w): w for w in work}
            for fut in cf.as_completed(futures):
                try:
                    done(fut.result())
                except Exception as exc:  # a worker process died: a finding, not the end
                    done(lost(futures[fut], exc))
    sys.stderr.write("\n")
    return sorted(records, key=lambda r: r["seed"])


def resumable(partial: Path, wanted: set[tuple[int, str, str]]) -> list[dict[str, Any]]:
    """The records of a stopped run's partial file that belong to this scenario set
    (one per seed; a line torn by the stop is left out and its scenario run again)."""
    found: dict[int, dict[str, Any]] = {}
    if partial.is_file():
        for line in partial.read_text(encoding="utf-8").splitlines():
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:
                continue
            key = (rec.get("seed"), rec.get("level"), rec.get("family", "classic")) \
                if isinstance(rec, dict) else None
            if key in wanted:
                found[rec["seed"]] = rec
    return list(found.values())


def bench(count: int, seed: int, jobs: int, rules_dir: str | None = None,
          cluster: str | None = None, partial: Path | None = None,
          resume: bool = False, families: Sequence[str] | None = None) -> dict[str, Any]:
    """Run the benchmark; returns the summary document, with the records as ``scenarios``.

    ``resume``: keep the records ``partial`` already holds and run only the others.
    """
    work = [(s, level, fam, rules_dir) for s, level, fam in tasks(count, seed, families)]
    kept = resumable(partial, {w[:3] for w in work}) if resume and partial else []
    done = {r["seed"] for r in kept}
    started = time.perf_counter()
    with executor(jobs, cluster) as (pool, runner):
        records = run_all([w for w in work if w[0] not in done], pool, partial, kept)
    return {"count": count, "seed": seed, "runner": runner,
            "wall_seconds": round(time.perf_counter() - started, 1),
            "summary": summarize(records, LEVELS),
            "families": summarize_families(records, LEVELS), "failures": failures(records),
            "scenarios": records}


def records_text(records: list[dict[str, Any]]) -> str:
    """JSON lines: one record per scenario, keys sorted so reruns compare line by line."""
    return "".join(json.dumps(r, sort_keys=True, ensure_ascii=False) + "\n" for r in records)


def _files(args: argparse.Namespace) -> tuple[Path, Path]:
    """The summary and records paths; exit 2 if either names a folder or they coincide."""
    out = Path(args.out)
    recs = Path(args.records) if args.records else out.with_suffix(".jsonl")
    if recs == out:
        raise InputError("the records file must differ from the summary file", where="--records")
    for path, flag in ((out, "--out"), (recs, "--records")):
        if path.is_dir():
            raise InputError("is a folder; give a file name", file=path, where=flag)
    return out, recs


def _command(args: argparse.Namespace) -> str:
    """The command line that reproduces the run's records."""
    where = f"--cluster {args.cluster}" if args.cluster else f"--jobs {args.jobs}"
    rules = f" --rules {args.rules}" if args.rules else ""
    fams = f" --families {args.families}" if args.families else ""
    return f"lbw bench --count {args.count} --seed {args.seed} {where}{rules}{fams}"


def run(args: argparse.Namespace) -> int:
    """Run, print the table and the failing cases, write the summary and the records."""
    if args.jobs is None:
        args.jobs = os.cpu_count() or 1
    if args.count < 1 or args.jobs < 1:
        raise InputError("--count and --jobs must be at least 1", where="arguments")
    if args.cluster:
        local_workers(args.cluster)  # a bad local:N is bad input before any work
    out, recs = _files(args)
    families = parse_families(args.families)
    if args.faults:  # faults are about the robot's repairs: on the classic structures unless asked
        families = families or ("classic",)
    rules = str(Path(args.rules).resolve()) if args.rules else None  # workers may start elsewhere
    # bad rules are bad input here, once, not a crash record per scenario (round 15, AO)
    _rules(rules)
    if args.scenarios:
        from perception.world.generator import generate

        with OutputDir(args.scenarios, inputs=[rules] if rules else [],
                       flag="--scenarios") as folder:
            for seed, level, fam in tasks(args.count, args.seed, families):
                folder.write_text(f"gen-{seed}-{level}.yaml",
                                  generate(seed, level, family=fam).text)
    if args.faults:
        from lbw_engine.cli.bench_faults import run_faults

        return run_faults(args, out, recs, rules, tasks(args.count, args.seed, families),
                          records_text)
    partial = recs.with_name(recs.name + ".partial")
    partial.parent.mkdir(parents=True, exist_ok=True)
    doc = bench(args.count, args.seed, args.jobs, rules, args.cluster, partial, args.resume,
                families)
    records = doc.pop("scenarios")
    doc["command"] = _command(args)
    doc["records"] = str(recs)
    atomic_write_text(recs, records_text(records))
    atomic_write_text(out, to_json(doc))
    partial.unlink(missing_ok=True)
    print(format_table(doc["summary"]))
    print(format_families(doc["families"]))
    print(f"{doc['count']} scenarios in {doc['wall_seconds']:.0f} s on {doc['runner']}; rates "
          f"with 95% Wilson intervals; {len(doc['failures'])} failing case(s):")
    for f in doc["failures"]:
        print(f"  seed {f['seed']} ({f['level']}, {f['family']}: {'+'.join(f['structures'])}, "
              f"{f['touches']} touch(es)): {'; '.join(f['what'])}")
    alarms = [r for r in records if r.get("monitor_detections")]
    executed = sum(1 for r in records if "monitor_detections" in r)
    print(f"runs with a monitor detection (no fault injected): {len(alarms)}/{executed}"
          + "".join(f"\n  seed {r['seed']} ({r['level']}, {r['family']}): "
                    f"{r['monitor_detections']} detection(s)" for r in alarms))
    print(f"summary: {out}; per-scenario records: {recs}")
    return 0
