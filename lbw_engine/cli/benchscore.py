"""How the benchmark scores one scenario against its truth (evaluation only).

The demonstration's script (a perception.world.scenario.Scenario) says what was built;
these read it next to what the pipeline learned: the final supports of the moved objects,
the aligns, and how far each recognized place put its block.
"""

from __future__ import annotations

import math
from typing import Any

from lbw_engine.report.metrics import support_facts


def true_final(scenario: Any, roles: Any) -> set:
    """(object, supports) after the demonstration, for every object the hand moved."""
    moved = {s.obj for s in scenario.demonstration if s.kind == "pick"}
    facts = support_facts(scenario.states[-1].relations(roles), roles.support)
    return {f for f in facts if f[0] in moved}


def true_aligns(scenario: Any, rules: Any) -> tuple[set, set]:
    """(must, may): unordered pairs of the objects the demonstration slid into line (design.md
    align) that a plan must hold, and those it may hold: a slide of at least
    rules/constants.yaml ``align-slide`` is an align, one within ``align-slide-doubt`` of it
    may be learned either way (``slide_reading``)."""
    from perception.world.layout import slide_reading

    least = float(rules.constants["align-slide"])
    doubt = float(rules.constants["align-slide-doubt"])
    must, may = set(), set()
    for s in scenario.demonstration:
        need, can = slide_reading(s, least, doubt)  # need implies can
        if can:
            may.add(frozenset((s.obj, s.align.with_)))
        if need:
            must.add(frozenset((s.obj, s.align.with_)))
    return must, may


def place_errors(sc: Any, roles: Any, true_ops: list, ops: list[dict[str, Any]]) -> list[float]:
    """How far (x, y; mm) each place measured its block from where the scenario puts it
    (the demonstration's script; tremor moves the real block by up to a few mm at 4x),
    for a sequence recognized as long as the true one, pairing operations of one kind."""
    if len(true_ops) != len(ops):
        return []
    out = []
    for t, op in zip(true_ops, ops, strict=True):
        if t.step < 0 or not t.special or sc.demonstration[t.step].kind != "place" \
                or any(r[0] == roles.hold for r in t.final_relations) \
                or op.get("operation") != t.operation:
            continue  # not the motion that let the block go (or not recognized as one)
        name = t.special[0]
        measured = (op.get("final_state") or {}).get("positions", {}).get(name)
        rest = sc.states[t.step].center.get(name)
        if measured is not None and rest is not None:
            out.append(round(math.dist(measured[:2], rest[:2]), 2))
    return out


def target_difference(true_ops: list, ops: list[dict[str, Any]],
                      rename: dict[str, str]) -> str | None:
    """The first operation whose targets differ from the truth's, for a sequence recognized
    exactly (``compare_sequence``): recognized names read as teach names (``rename``);
    None when every target agrees. The trailing repeats of the last operation count as
    one, as in the sequence's exactness."""
    from lbw_engine.report.metrics import collapse_tail

    truth = collapse_tail([{"operation": t.operation, "target": list(t.target)}
                           for t in true_ops])
    got = collapse_tail(ops)
    for k, (t, op) in enumerate(zip(truth, got, strict=False)):
        seen = sorted(rename.get(n, n) for n in op.get("target") or [])
        if seen != sorted(t["target"]):
            return f"at #{k} {t['operation']}: expected {sorted(t['target'])}, got {seen}"
    return None


def first_failure(phases: dict[str, str], foreign: str | None) -> str | None:
    """A record's ``failure``: the right operations on objects the teach workspace does not
    hold fail recognition; otherwise the first phase after recognition that failed (a
    sequence difference is the record's ``exact``), as ``phase: why``."""
    if foreign:
        return f"recognition: {foreign}"
    return next((f"{k}: {v}" for k, v in phases.items() if k != "recognition"), None)


def failures(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Every scenario that was not recognized exactly, not planned right or not executed."""
    out = []
    for r in records:
        what = []
        if "exact" in r and not r["exact"]:
            mended = " (repaired to the demonstrated one)" if r.get("exact_repaired") else ""
            what.append(f"sequence {r['difference']}{mended}")
        elif r.get("target_difference"):
            what.append(f"targets {r['target_difference']}")
        if "error" in r:
            what.append(f"crashed: {r['error']}")
        else:
            if r.get("failure"):
                what.append(r["failure"])
            elif not r.get("aligns_correct", True):
                what.append("the plan's aligns differ from the demonstrated ones")
            elif not r["plan_correct"]:
                what.append("plan's final relations differ from the true ones")
        if what:
            out.append({"seed": r["seed"], "level": r["level"],
                        "family": r.get("family", "classic"), "structures": r["structures"],
                        "touches": r["touches"], "what": what})
    return out
