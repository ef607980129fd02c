"""commands.txt: a traced plan printed in the manner of Fig. 24.

Per plan operator its class and name; per recognized operation its goal —
GOAL-POSITION as Fig. 24's 6-vector (centre, then turns about x, y and the
vertical; the last is the wrist's, design.md "Robot") and the tool point in
arm coordinates — then the operation's label and its manipulator commands.
Comments (``;``) say where the tracer departed from the plain expansion: a
placement moved so its load stands, a fine motion, blocks set aside first, a
harmless leaf left out.
"""

from __future__ import annotations

from lbw_engine.do.expander import fvec
from lbw_engine.do.tracing import Trace, TracedOp


def format_commands(tr: Trace, title: str = "") -> str:
    """commands.txt in the manner of Fig. 24: operator, goal, operation, commands."""
    n = len(tr.commands)
    lines = [f";;; {title} — {n} manipulator commands (positions in arm coordinates, mm)"
             if title else f";;; {n} manipulator commands (positions in arm coordinates, mm)"]
    last_op = last_goal = None
    for op in tr.ops:
        if op.skipped:  # a harmless leaf (commands.yaml harmless) that could not be done
            lines.append(f" ; left out: {op.skipped}")
        if not op.commands:
            continue
        if op.operator != last_op:
            lines.append(f"<<{op.operator_class.capitalize()}>> {op.operator}")
            last_op, last_goal = op.operator, None
        done = 0
        for note, count, _, _ in op.aside:  # blocks set aside before the pick (clearing.py)
            lines += [f" ; {note}", " <set-aside>"]
            lines.extend(f" {c.text()}" for c in op.commands[done:done + count])
            done += count
        if op.goal is not None and (op.goal, op.wrist) != last_goal:
            lines.append(f" GOAL-POSITION {_pose(op)}")
            lines.append(f" ARM GOAL POSITION {fvec(op.arm_goal)}")
            if op.steadied:
                lines.append(f" ; moved {op.steadied:.1f} mm from the taught spot so that "
                             f"'{op.focus}' and its load stand on the supports")
            last_goal = (op.goal, op.wrist)
        if op.fine:
            lines.append(f" ; fine motion: set down clear of the contact, {op.fine} into it")
        lines.append(f" <{op.operation.lower()}>")
        lines.extend(f" {c.text()}" for c in op.commands[done:])
    return "\n".join(lines) + "\n"


def _pose(op: TracedOp) -> str:
    """The goal as Fig. 24's 6-vector: centre (mm), then the turn about x, y and the vertical
    (degrees); the last is the wrist's, the jaws' closing direction from world x."""
    return fvec((*op.goal, 0.0, 0.0, op.wrist or 0.0))
