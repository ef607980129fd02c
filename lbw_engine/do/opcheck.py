"""The robot's recognized operations against the executed ones (Sec. IX-C2, issue #13).

The execution monitor watches the robot with the demonstration's recognizer
(lbw_engine.pipeline.robotwatch) and, after each ACHIEVE, compares what it
recognized with the unit's traced operations. A robot does not move like a
person: straight Cartesian moves, pauses while the wrist turns and the jaws
open or close. Its REACHes, WITHDRAWs and fine motions are segmented
differently from a hand's, so they are reported, not judged. What must agree
is what changes the world: the operations whose effect (effects.yaml) moves an
object, i.e. takes it into the hand (``follow``) or puts it onto a support
(``place``). Those must be recognized in the executed order, of the same class
(the effect's kind of move) and on the same object. Which support a place is
onto (the table or a block: a separate operation in Table V) is left to the
state comparison, which measures it; but a place must be seen where it was
executed: the point where the recognizer measured the object appear (the
effect's ``measured`` feature) within PLACE_MM of the executed goal, in x and
y (a block dropped on the way is seen put down elsewhere). Which operations
those are, their
classes and the effect variable that names the moved object are read from the
rules; no operation name is written here. Blocks set aside before an operation
(clearing.py) are expected as one move of each class, labelled ``SET_ASIDE``
in reports; so is a block the closed jaws push into contact (``PUSHED``). Both
are expected if seen, never required.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.do.fine import PUSH
from lbw_engine.do.tracing import TracedOp

PLACE_MM = 40.0  # a place seen farther than this (x, y) from its executed goal was elsewhere
SET_ASIDE = "set aside"  # how reports name the moves of a block put down out of the way
PUSHED = "pushed"  # how reports name a block's moves as the closed jaws slide it (fine.py)


@dataclass(frozen=True)
class Op:
    """An operation, its class (the effect's kind of move) and the object it moves (None
    when it names none). Two are the same when class and object are."""

    operation: str = field(compare=False)
    object: str | None
    kind: str = ""
    at: tuple[float, ...] | None = field(default=None, compare=False)  # where it was put
    # blocks riding on the moved one: the watch may name one of them, whose top face is
    # the one it sees move (helper round 16, 51: a tower's middle cube lifted with the
    # top one on it was watched as the top one taken, and the unit redone)
    carries: frozenset[str] = field(default=frozenset(), compare=False)

    def text(self) -> str:
        """``OPERATION object`` (``at (x, y)`` when placed), for reports."""
        out = self.operation if self.object is None else f"{self.operation} {self.object}"
        return out if self.at is None else f"{out} at ({self.at[0]:.0f}, {self.at[1]:.0f})"


def moving_operations(effects: Mapping[str, Any]) -> dict[str, tuple[str, str, str | None]]:
    """Operation -> (class, effect variable of the object it moves, feature measuring where
    it was put), for every operation whose effect rule (effects.yaml ``move``) moves one:
    into the hand (class ``follow``, variable ``object``, no feature) or onto a support
    (class ``place``, the variable it places, its ``measured`` feature)."""
    out: dict[str, tuple[str, str, str | None]] = {}
    for name, rule in effects.items():
        move = rule.move or {}
        kind = "follow" if "follow" in move else "place"
        var = move.get("object") if kind == "follow" else move.get("place")
        if isinstance(var, str):
            out[name] = (kind, var.lstrip("$"), move.get("measured") if kind == "place" else None)
    return out


def executed_ops(ops: Sequence[TracedOp], moving: Mapping[str, tuple]) -> list[Op]:
    """The unit's executed operations that move an object, in order (skipped ones left out);
    a place's ``at`` is its goal. A block set aside before an operation (a rider the plan
    does not carry, a regrasp: clearing.py) was taken and put down on the table first."""
    out = []
    for o in ops:
        if o.skipped:
            continue
        for _, _, name, spot in o.aside:
            out += [Op(SET_ASIDE, name, "follow"), Op(SET_ASIDE, name, "place", _xy(spot))]
        if o.operation in moving:
            out.append(Op(o.operation, o.focus, moving[o.operation][0],
                          _xy(o.goal) if moving[o.operation][2] else None,
                          frozenset(o.carries)))
        if o.fine == PUSH:
            # the closed jaws slide the released block into contact: the watch may see
            # it taken and put down again (helper round 10, x27: a PICK)
            out += [Op(PUSHED, o.focus, "follow"), Op(PUSHED, o.focus, "place")]
    return out


def recognized_ops(nodes: Sequence[Any], moving: Mapping[str, tuple]) -> list[Op]:
    """Recognized ACT-nodes (the root's history) that move an object, with the object their
    effect bound (``ActNode.bound``, recorded when they were classified)."""
    out = []
    for node in nodes:
        if node.operation in moving:
            kind, var, feature = moving[node.operation]
            names = tuple(node.bound.get(var, ()))
            at = _xy(node.measured.get(feature)) if feature else None
            out.append(Op(node.operation, names[0] if names else None, kind, at))
    return out


def _xy(point: Any) -> tuple[float, float] | None:
    """A point's x and y, None for none."""
    return None if point is None else (float(point[0]), float(point[1]))


def elsewhere(expected: Op, seen: Op) -> bool:
    """A place seen farther than PLACE_MM from where it was executed (both measured)."""
    return expected.at is not None and seen.at is not None and \
        math.dist(expected.at, seen.at) > PLACE_MM


def differences(expected: Sequence[Op], seen: Sequence[Op]) -> list[dict[str, Any]]:
    """Where the recognized sequence differs from the executed one, aligned in order.

    Each difference is ``{object, expected, observed}``: an executed operation not seen
    (``observed`` None), one seen in place of another (of another class, or on another
    object), one seen that was not executed (``expected`` None), or a place seen
    elsewhere; a move seen as the move of a block riding on the one moved is none. A
    block set aside is expected, so that seeing it is no difference, but
    not required: the watch may miss it (a tile taken off a stack at 4x, bench 1107),
    and it is no plan object to check or redo.
    """
    out: list[dict[str, Any]] = []
    matcher = difflib.SequenceMatcher(a=list(expected), b=list(seen), autojunk=False)
    for tag, i0, i1, j0, j1 in matcher.get_opcodes():
        exp, got = list(expected[i0:i1]), list(seen[j0:j1])
        if tag == "equal":
            out += [_diff(e, g) for e, g in zip(exp, got, strict=True) if elsewhere(e, g)]
            continue
        for k in range(max(len(exp), len(got))):
            e, g = exp[k] if k < len(exp) else None, got[k] if k < len(got) else None
            if e is not None and (g is None or g.kind == e.kind) and \
                    (e.operation == SET_ASIDE or e.operation == PUSHED
                     and (g is None or g.object == e.object)):
                # a set-aside or a push the watch missed, or saw (a set-aside under its own
                # name for a block the plan does not have): expected if seen, never required
                continue
            if e is not None and g is not None and g.kind == e.kind and \
                    g.object in e.carries and not elsewhere(e, g):
                continue  # the move of a block with riders, seen as one of theirs
            out.append(_diff(e, g))
    return out


def _diff(e: Op | None, g: Op | None) -> dict[str, Any]:
    """One difference record (``unplaced``: an executed place of the plan not seen as
    executed; a block set aside is no plan object, and nothing redoes it)."""
    obj = e.object if e is not None else g.object if g is not None else None
    return {"object": obj, "expected": e.text() if e else None,
            "observed": g.text() if g else None,
            "unplaced": e is not None and e.kind == "place" and e.object is not None
            and e.operation != SET_ASIDE}


def unplaced(diffs: Sequence[dict]) -> set[str]:
    """Objects whose executed place was not seen, or seen elsewhere or as another
    operation: something else moved them (a drop), so where they lie is suspect even
    when the cameras measure them within tolerance of their goal."""
    return {d["object"] for d in diffs if d.get("unplaced")}


def operation_detections(operator: str, diffs: Sequence[dict], t: float) -> list[dict]:
    """execution.json ``monitor.detections`` records (kind ``operation``) for one unit."""
    return [{"operator": operator, "object": d["object"], "expected": d["expected"],
             "observed": d["observed"], "t": round(t, 2), "kind": "operation"} for d in diffs]
