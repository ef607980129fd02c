"""The robot's recognized operations against the executed ones (Sec. IX-C2, issue #13).

The execution monitor watches the robot with the demonstration's recognizer
(lbw_engine.pipeline.robotwatch) and, after each ACHIEVE, compares what it
recognized with the unit's traced operations. A robot does not move like a
person: straight Cartesian moves, pauses while the wrist turns and the jaws
open or close. Its REACHes, WITHDRAWs and fine motions are segmented
differently from a hand's, so they are reported, not judged. What must agree
is what changes the world: the operations whose effect (effects.yaml) moves an
object, i.e. takes it into the hand or puts it onto a support. Those must be
recognized in the executed order, with the same operation and the same
object. Which operations those are, and which effect variable names the moved
object, is read from the rules; no operation name is written here.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from lbw_engine.do.tracing import TracedOp


@dataclass(frozen=True)
class Op:
    """An operation and the object it moves (None when it names none)."""

    operation: str
    object: str | None

    def text(self) -> str:
        """``OPERATION object``, for reports."""
        return self.operation if self.object is None else f"{self.operation} {self.object}"


def moving_operations(effects: Mapping[str, Any]) -> dict[str, str]:
    """Operation -> the effect variable of the object it moves, for every operation whose
    effect rule (effects.yaml ``move``) moves one: into the hand (``follow``, ``object``) or
    onto a support (``place``)."""
    out: dict[str, str] = {}
    for name, rule in effects.items():
        move = rule.move or {}
        var = move.get("object") if "follow" in move else move.get("place")
        if isinstance(var, str):
            out[name] = var.lstrip("$")
    return out


def executed_ops(ops: Sequence[TracedOp], moving: Mapping[str, str]) -> list[Op]:
    """The unit's executed operations that move an object, in order (skipped ones left out)."""
    return [Op(o.operation, o.focus) for o in ops if o.operation in moving and not o.skipped]


def recognized_ops(nodes: Sequence[Any], moving: Mapping[str, str]) -> list[Op]:
    """Recognized ACT-nodes (the root's history) that move an object, with the object their
    effect bound (``ActNode.bound``, recorded when they were classified)."""
    out = []
    for node in nodes:
        if node.operation in moving:
            names = tuple(getattr(node, "bound", {}).get(moving[node.operation], ()))
            out.append(Op(node.operation, names[0] if names else None))
    return out


def differences(expected: Sequence[Op], seen: Sequence[Op]) -> list[dict[str, Any]]:
    """Where the recognized sequence differs from the executed one, aligned in order.

    Each difference is ``{object, expected, observed}``: an executed operation not seen
    (``observed`` None), one seen in place of another (another operation, or the same on
    another object), or one seen that was not executed (``expected`` None).
    """
    out: list[dict[str, Any]] = []
    matcher = difflib.SequenceMatcher(a=list(expected), b=list(seen), autojunk=False)
    for tag, i0, i1, j0, j1 in matcher.get_opcodes():
        if tag == "equal":
            continue
        exp, got = list(expected[i0:i1]), list(seen[j0:j1])
        for k in range(max(len(exp), len(got))):
            e = exp[k] if k < len(exp) else None
            g = got[k] if k < len(got) else None
            obj = e.object if e is not None else g.object if g is not None else None
            out.append({"object": obj, "expected": e.text() if e else None,
                        "observed": g.text() if g else None})
    return out


def operation_detections(operator: str, diffs: Sequence[dict], t: float) -> list[dict]:
    """execution.json ``monitor.detections`` records (kind ``operation``) for one unit."""
    return [{"operator": operator, "object": d["object"], "expected": d["expected"],
             "observed": d["observed"], "t": round(t, 2), "kind": "operation"} for d in diffs]
