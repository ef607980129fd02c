"""Ground truth of a demonstration, for evaluating the recognizer only.

From a scenario and the demonstrator's own schedule: the top-level operation
sequence (Table V's names; Fig. 12 and Fig. 20), each operation's true time
span, targets and the true support relations before and after it. The
recognizer, its detectors and lbw_engine never import this module
(tests/test_boundaries.py).

Segmentation convention (Sec. V-B): a Transfer runs from the end of the
previous Depart to the hand's arrival above the next target; the LocalMotion
then runs until the hand has risen again (end of its Depart). The final
Transfer, the hand leaving the workspace, is the one WITHDRAW. (The paper's
Fig. 12 shows two closing withdraws: the recognizer may split the leaving
motion; a comparison should treat consecutive WITHDRAWs as one.)
"""

from __future__ import annotations

from dataclasses import dataclass

from perception.world.demonstrator import Demonstration, Segment
from perception.world.layout import Layout

# step kind -> (Transfer operation, LocalMotion operation); a place on blocks is
# refined below. Table V: REACH / REACH-WITH-OBJ end a Transfer at :Near.
_OPERATIONS = {
    "pick": ("REACH", "PICK"),
    "touch": ("REACH", "NO-OP"),
    "place": ("REACH-WITH-OBJ", "PLACE-ON-TABLE"),
}


@dataclass(frozen=True)
class TrueFine:
    """A fine operation inside a LocalMotion (ALIGN, Sec. V-B5)."""

    operation: str
    t_start: float
    t_end: float


@dataclass(frozen=True)
class TrueOperation:
    """One top-level operation as it really happened."""

    operation: str
    motion: str  # "Transfer" | "LocalMotion"
    t_start: float
    t_end: float
    step: int  # demonstration step index, -1 for the closing withdraw
    target: tuple[str, ...]
    special: tuple[str, ...]
    initial_relations: list
    final_relations: list
    fine: tuple[TrueFine, ...] = ()


def _local_name(step, kind_ops: tuple[str, str]) -> str:
    """PLACE-ON-BLOCK when the place's supports are objects, else the table's name."""
    if step.kind == "place" and step.on != ("table",):
        return "PLACE-ON-BLOCK"
    return kind_ops[1]


def expected_operations(scenario) -> list[str]:
    """The top-level operation names the recognizer should report, in order."""
    out: list[str] = []
    for step in scenario.demonstration:
        ops = _OPERATIONS[step.kind]
        out += [ops[0], _local_name(step, ops)]
    return out + ["WITHDRAW"]


def ground_truth(scenario, demonstration: Demonstration | None = None) -> list[TrueOperation]:
    """True operations with times (from the demonstrator's schedule) and relations."""
    demo = demonstration or Demonstration(scenario)
    by_step: dict[int, list[Segment]] = {}
    for seg in demo.segments:
        by_step.setdefault(seg.step, []).append(seg)
    before: Layout = scenario.teach.layout()
    out: list[TrueOperation] = []
    for i, step in enumerate(scenario.demonstration):
        segs = by_step[i]
        after = scenario.states[i]
        transfer = next(s for s in segs if s.phase == "transfer")
        ops = _OPERATIONS[step.kind]
        if step.kind == "place":
            target, special = step.on, (step.obj,)
        else:
            target, special = (step.obj,), ()
        rel0, rel1 = before.relations(), after.relations()
        out.append(TrueOperation(ops[0], "Transfer", transfer.t0, transfer.t1, i, target,
                                 special, rel0, rel0))
        fine: tuple[TrueFine, ...] = ()
        slides = [s for s in segs if s.phase == "fine" and s.p0 != s.p1]
        if step.align is not None and slides:
            fine = (TrueFine("ALIGN", slides[0].t0, slides[-1].t1),)
        out.append(TrueOperation(_local_name(step, ops), "LocalMotion", transfer.t1, segs[-1].t1,
                                 i, target, special, rel0, rel1, fine))
        before = after
    leave = next(s for s in by_step[-1] if s.phase == "transfer")
    rel = before.relations()
    out.append(TrueOperation("WITHDRAW", "Transfer", leave.t0, leave.t1, -1, (), (), rel, rel))
    return out
