"""``lbw bench --faults``: the robot watching itself, on generated scenarios (issue #13).

Each generated scenario is watched and analyzed once (as in ``lbw bench``); its
learned plan is then executed several times in the scenario's execution
workspace: without faults, and with faults drawn from the seed (design.md
``execute.faults``): a drop, a displace, a remove without and with a spare of
the removed object's shape, a drop with a displace, and a nudge of 6-12 mm once the
structure is built. Scored per injected
fault, from the execution reports (ground truth only for scoring):

* detected — a monitor detection at or after the fault, before the next one;
  a fault on an object the plan does not use needs none and is counted apart;
* repaired — the run ends verified by the cameras (and the ground truth);
* repairable — unless the world made it impossible: an object the plan uses
  removed (or slid off the table's edge) with no spare of its shape, or a block
  lying on its side (the robot's grasps keep a block's orientation; the ground
  truth confirms it);
* every run that is not repaired must end with a reason (exit 1).

A plan learned wrong cannot be done with or without faults (its fault-free run
fails, and so does the plan executed unmonitored): the monitor rightly reports
its wrong structure. Such a scenario's runs measure the recognizer (issue #12),
not the monitor, so they are counted apart (``plan_executable`` in the records).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lbw_engine.do.verification import POSITION_TOLERANCE_MM
from lbw_engine.names import TABLE

KINDS = ("none", "drop", "displace", "remove", "remove-spare", "drop+displace", "nudge")
SHIFT_MM = (50.0, 90.0)  # how far a displace slides an object
# ... and a nudge, after the last ACHIEVE, along x or y: past the 5 mm position tolerance,
# a block under others moves its image by 2-4 pixels (helper round 15's AN)
NUDGE_MM = (6.0, 12.0)


def run_faults_one(task: tuple[int, str, str | None, str]) -> list[dict[str, Any]]:
    """Watch and analyze one generated scenario, then execute its plan once per fault kind."""
    import traceback

    seed, level, rules_dir, family = task
    from perception.world.generator import generate

    gen = generate(seed, level, family=family)
    base = {"seed": seed, "level": level, "family": family,
            "structures": list(gen.structures)}
    try:
        plan, rules = _learn(gen.scenario(), rules_dir)
    except Exception as exc:  # a finding of the benchmark, not its end
        return [{**base, "kind": "none", "error": f"{type(exc).__name__}: {exc}",
                 "traceback": traceback.format_exc(limit=-6)}]
    if plan is None:
        # a recognition failure (analysis refused the sequence), not a crash
        return [{**base, "kind": "none", "no_plan": "the demonstration did not give a plan"}]
    rng = np.random.default_rng(seed)
    out = []
    executable = True
    for kind in KINDS:
        faults, extra = draw_faults(kind, gen.scenario(), plan, rng)
        if faults is None:
            continue
        rec = {**base, "kind": kind}
        try:
            _execute(rec, gen.text, faults, extra, plan, rules)
            if kind == "none":
                executable = _executable(rec, gen.text, plan, rules)
        except Exception as exc:
            rec["error"] = f"{type(exc).__name__}: {exc}"
            rec["traceback"] = traceback.format_exc(limit=-6)
        rec["plan_executable"] = executable
        out.append(rec)
    return out


def _executable(rec: dict[str, Any], text: str, plan: Any, rules: Any) -> bool:
    """Whether the learned plan can be done at all: its fault-free run verified by the
    simulator, or, when it did not, the plan executed unmonitored (``--via bt``) without
    faults verifies. A plan learned wrong (a recognition error, issue #12: a place on the
    table read as a place across its two neighbours) cannot; its runs measure the
    recognizer, not the monitor, and are counted apart."""
    from lbw_engine.pipeline.execute import execute_plan
    from perception.world.scenario import load_text

    if rec.get("success") and (rec.get("verification") or {}).get("ground_truth"):
        return True
    result = execute_plan(plan, load_text(text, f"<faults seed {rec['seed']} plan>"), rules,
                          via="bt")
    return bool((result.report.get("verification") or {}).get("ground_truth"))


def _learn(sc: Any, rules_dir: str | None) -> tuple[Any, Any]:
    """Watch → repair → analyze, as ``lbw run`` does: the learned plan (None if analysis
    refused it) and the rules."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.errors import InputError
    from lbw_engine.pipeline.run import analyze_actions
    from lbw_engine.pipeline.watch import repair, watch
    from lbw_engine.rules import load_rules
    from lbw_engine.see.actions import to_actions

    rules = load_rules(rules_dir)
    recognizer, _ = watch(sc, rules)
    actions = repair(to_actions(recognizer), rules).actions  # Sec. IX-C2, as in lbw run
    try:
        return planmod.parse(analyze_actions(actions, rules).plan, file="plan.json"), rules
    except InputError:
        return None, rules


def draw_faults(kind: str, sc: Any, plan: Any, rng: np.random.Generator
                ) -> tuple[list[str] | None, str]:
    """Fault lines (YAML flow mappings) and extra execution objects for one run, or
    None when the scenario offers no such fault (e.g. no free spot to slide to)."""
    from lbw_engine.do.matching import plan_objects
    from lbw_engine.do.monitor import UNIT_CLASS

    n = sum(1 for op in plan.operators.values() if op.cls == UNIT_CLASS)

    taught = plan.objects or {n: {"shape": o.shape} for n, o in sc.teach.objects.items()}
    used = {taught[n]["shape"] for n in plan_objects(plan) if n in taught}
    names = sorted(n_ for n_, o in sc.execute.objects.items() if o.shape in used)
    if kind == "none":
        return [], ""
    if not names or n < 1:
        return None, ""
    lines, extra = [], ""
    for part in kind.split("+"):
        when = int(rng.integers(1, n + 1))
        if part == "drop":
            lines.append(f"{{during: {when}, kind: drop}}")
        elif part == "nudge":
            obj = names[int(rng.integers(len(names)))]
            d = float(rng.uniform(*NUDGE_MM)) * (1.0 if rng.integers(2) else -1.0)
            by = (d, 0.0) if rng.integers(2) else (0.0, d)
            lines.append(f"{{after: {n}, kind: displace, object: {obj}, "
                         f"by: [{by[0]:.0f}, {by[1]:.0f}]}}")
        elif part == "displace":
            obj = names[int(rng.integers(len(names)))]
            by = _free_shift(sc, obj, rng)
            if by is None:
                return None, ""
            lines.append(f"{{after: {when}, kind: displace, object: {obj}, "
                         f"by: [{by[0]:.0f}, {by[1]:.0f}]}}")
        else:
            obj = names[int(rng.integers(len(names)))]
            lines.append(f"{{after: {when}, kind: remove, object: {obj}}}")
            if part == "remove-spare":
                spot = _free_spot(sc, sc.execute.objects[obj].size, rng)
                if spot is None:
                    return None, ""
                extra = (f"    spare-{obj}: {{shape: {sc.execute.objects[obj].shape}, "
                         f"at: [{spot[0]:.0f}, {spot[1]:.0f}]}}\n")
    return lines, extra


def _taken(sc: Any, skip: str | None = None) -> list[tuple]:
    """Footprints to keep clear: execution objects and the taught final structure."""
    from perception.world.generator import footprint

    boxes = [(o.center, o.size) for n, o in sc.execute.objects.items() if n != skip]
    final = sc.states[-1] if sc.states else None
    if final is not None:
        boxes += [(final.center[n], final.size[n]) for n in final.center]
    return [footprint(c[0], c[1], s[0], s[1]) for c, s in boxes]


def _free_shift(sc: Any, obj: str, rng: np.random.Generator) -> tuple[float, float] | None:
    """A slide of ``obj`` to a clear spot, 50-90 mm away (a few random tries)."""
    from perception.world.generator import clear, footprint

    o = sc.execute.objects[obj]
    if o.on != (TABLE,):
        return None  # slide only what stands on the table; its riders may fall
    taken = _taken(sc, skip=obj)
    for _ in range(60):
        a = rng.uniform(0, 2 * math.pi)
        d = rng.uniform(*SHIFT_MM)
        by = (round(d * math.cos(a)), round(d * math.sin(a)))
        if clear(footprint(o.center[0] + by[0], o.center[1] + by[1], o.size[0], o.size[1]),
                 taken):
            return by
    return None


def _free_spot(sc: Any, size: tuple, rng: np.random.Generator) -> tuple[float, float] | None:
    """A clear table spot for a spare of ``size`` (the generator's search), or None."""
    from perception.world.generator import Crowded, free_spot

    try:
        x, y, _ = free_spot(rng, size, _taken(sc))
    except Crowded:
        return None
    return x, y


def _execute(rec: dict[str, Any], text: str, faults: list[str], extra: str, plan: Any,
             rules: Any) -> None:
    """Execute ``plan`` in the scenario with the faults; score the run into ``rec``."""
    from lbw_engine.pipeline.execute import execute_plan
    from perception.world.scenario import load_text

    body = text.rstrip("\n") + "\n" + extra
    if faults:
        body += "  faults:\n" + "".join(f"    - {f}\n" for f in faults)
    sc = load_text(body, f"<faults seed {rec['seed']} {rec['kind']}>")
    result = execute_plan(plan, sc, rules)
    rep = result.report
    rec.update(success=bool(result.success), failure=rep.get("failure"),
               verification=rep.get("verification"), stage=rep.get("stage"),
               faults=rep.get("faults", []),
               detections=rep.get("monitor", {}).get("detections", []),
               repairs=rep.get("monitor", {}).get("repairs", []),
               toppled=rep.get("ground_truth_toppled", []))
    relevant = _relevant(sc, rep)
    for f in rec["faults"]:
        f["relevant"] = counts(f, relevant)
    for f in rec["faults"]:  # faults at one ACHIEVE's end share the look after it
        later = [g["t"] for g in rec["faults"] if g["achieve"] > f["achieve"]]
        end = min(later, default=math.inf)
        f["detected"] = any(f["t"] <= d["t"] <= end for d in rec["detections"])
    rec["repairable"] = repairable(rec["faults"], rec["toppled"], spare=bool(extra))


def counts(fault: dict[str, Any], used: set[str]) -> bool:
    """Whether an injected fault must be detected: every drop; a displace or remove of an
    object the plan uses (``used``: execution names), but not a displace that moved it
    less than the verdict's position tolerance, which changed nothing a camera or the
    ground truth can tell (a cube wedged in a pyramid's row, nudged along y into its
    neighbour: fault bench 7000)."""
    if fault["kind"] == "drop":
        return True
    return fault.get("object") in used and \
        fault.get("moved_mm", math.inf) >= POSITION_TOLERANCE_MM


def repairable(faults: list[dict[str, Any]], toppled: list[str], spare: bool) -> bool:
    """Whether the world left the run repairable: no block on its side, and no object the
    plan uses taken away (removed, or slid past the table's edge) without a spare."""
    return not (toppled or any((f["kind"] == "remove" or f.get("off_table"))
                               and f["relevant"] and not spare for f in faults))


def _relevant(sc: Any, report: dict[str, Any]) -> set[str]:
    """Execution objects the plan used: nearest to the matched measured positions."""
    matched = report.get("initial_state", {}).get("matching", {})
    out = set()
    for pos in matched.values():
        out.add(min(sc.execute.objects,
                    key=lambda n: math.dist(sc.execute.objects[n].center[:2], pos[:2])))
    return out


def summarize_faults(records: list[dict[str, Any]]) -> dict[str, Any]:
    """The issue's figures over all runs."""
    learned = [r for r in records if "error" not in r and "no_plan" not in r]
    wrong_plans = [r for r in learned if r["kind"] == "none" and not r.get("plan_executable", True)]
    runs = [r for r in learned if r.get("plan_executable", True)]
    free = [r for r in runs if r["kind"] == "none"]
    faulty = [r for r in runs if any(f["relevant"] for f in r["faults"])]
    injected = [f for r in runs for f in r["faults"] if f["relevant"]]
    repairable = [r for r in faulty if r["repairable"]]
    unrepaired = [r for r in faulty if not r["success"]]
    # agreement is scored where a finished run was verified (a stopped run's two "no"s
    # would only inflate it); records before the stage was kept have no stage
    verdicts = [r for r in runs if isinstance(r.get("verification"), dict)
                and r.get("stage", "verification") == "verification"]
    return {
        "runs": len(records), "crashed": sum(1 for r in records if "error" in r),
        "plans_not_executable": len(wrong_plans),
        "no_plan": sum(1 for r in records if "no_plan" in r),
        "fault_free_runs": len(free),
        "fault_free_without_detection": sum(1 for r in free if not r["detections"]),
        "faults_injected": len(injected),
        "faults_on_unused_objects": sum(1 for r in runs for f in r["faults"]
                                        if not f["relevant"]),
        "faults_detected": sum(1 for f in injected if f["detected"]),
        "faulty_runs": len(faulty), "repairable_runs": len(repairable),
        "repairable_repaired": sum(1 for r in repairable if r["success"]),
        "unrepaired_runs": len(unrepaired),
        "unrepaired_with_reason": sum(1 for r in unrepaired if r.get("failure")),
        "verdict_runs": len(verdicts),
        "verdicts_agree": sum(1 for r in verdicts
                              if r["verification"]["cameras"] ==
                              r["verification"]["ground_truth"]),
    }


def format_faults(s: dict[str, Any]) -> str:
    """The figures as lines of text."""
    def pct(a: int, b: int) -> str:
        return f"{a}/{b} ({a / b:.0%})" if b else f"{a}/0"

    return "\n".join([
        f"faults detected:                {pct(s['faults_detected'], s['faults_injected'])}"
        f" (+{s['faults_on_unused_objects']} on objects the plan does not use)",
        "fault-free runs, no detection:  "
        f"{pct(s['fault_free_without_detection'], s['fault_free_runs'])}",
        f"repairable runs repaired:       {pct(s['repairable_repaired'], s['repairable_runs'])}"
        f" (of {s['faulty_runs']} runs with faults)",
        f"unrepaired runs with a reason:  {pct(s['unrepaired_with_reason'], s['unrepaired_runs'])}",
        f"cameras agree with the truth:   {pct(s['verdicts_agree'], s['verdict_runs'])}",
        f"runs: {s['runs']}, crashed: {s['crashed']}, scenarios that gave no plan: "
        f"{s.get('no_plan', 0)}, plans that fail without faults (learned wrong; their runs "
        f"not counted above): {s.get('plans_not_executable', 0)}",
    ])


def run_faults(args: Any, out: Any, recs: Any, rules_dir: str | None,
               scenario_set: list[tuple[int, str, str]], records_text: Any) -> int:
    """``lbw bench --faults``: run, print the figures, write the summary and the records.

    ``scenario_set`` and ``records_text`` are lbw bench's (same seeds, same JSON lines)."""
    import time

    from lbw_engine.cli.cluster import executor
    from lbw_engine.outputs import atomic_write_text, to_json

    work = [(s, level, rules_dir, fam) for s, level, fam in scenario_set]
    started = time.perf_counter()
    records: list[dict[str, Any]] = []
    with executor(args.jobs, args.cluster) as (pool, runner):
        if pool is None:
            for w in work:
                records += run_faults_one(w)
        else:
            for recs_one in pool.map(run_faults_one, work):
                records += recs_one
    records.sort(key=lambda r: (r["seed"], KINDS.index(r["kind"])))
    summary = summarize_faults(records)
    where = f"--cluster {args.cluster}" if args.cluster else f"--jobs {args.jobs}"
    doc = {"count": args.count, "seed": args.seed, "runner": runner,
           "wall_seconds": round(time.perf_counter() - started, 1), "summary": summary,
           "command": f"lbw bench --faults --count {args.count} --seed {args.seed} {where}",
           "records": str(recs)}
    atomic_write_text(recs, records_text(records))
    atomic_write_text(out, to_json(doc))
    print(format_faults(summary))
    for r in records:
        if "error" in r or "no_plan" in r or (not r["success"] and r.get("repairable", True)) \
                or (r["kind"] == "none" and r["detections"]):
            why = r.get("error") or r.get("no_plan") or r.get("failure") or \
                "detections without a fault"
            print(f"  seed {r['seed']} {r['kind']}: {why}")
    print(f"summary: {out}; per-run records: {recs}")
    return 0
