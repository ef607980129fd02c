"""Room for the gripper's jaws: where to grip an object so the fingers hit nothing.

The paper grips every object at its centre (Sec. VII-B) and names the lack of
a grasp planner as a limitation (Sec. IX-B). In a crowded workspace a finger
coming down next to an object can knock over a neighbour, so the grip point
may slide along the object's edge, away from the jaw axis, to the first offset
whose jaw regions are free. A jaw region spans from the object's side to the
open finger's outer face, and from the fingertips up to above the approach
height; the held object and what rides on it are not obstacles. A gap of
``gripper.clearance`` is kept, since positions are measured by the cameras.
"""

from __future__ import annotations

from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Vec, overlap
from lbw_engine.rules.commands import CommandRules

STEP_MM = 5.0  # spacing of candidate grip offsets


def jaw_regions(centre: Vec, size: Vec, dy: float, rules: CommandRules) -> list[tuple[Vec, Vec]]:
    """The two boxes the fingers sweep when gripping an object at ``centre`` + ``dy``."""
    j = rules.jaw_axis
    o = 1 - j
    grip_z = centre[2] + rules.grip_offset(size)
    z0 = grip_z - rules.tip
    z1 = max(grip_z, rules.approach_height) - rules.tip + rules.finger[2]
    inner = size[j] / 2
    outer = (size[j] + rules.margin) / 2 + rules.finger[0]
    boxes = []
    for side in (-1, 1):
        c, s = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        c[j], s[j] = centre[j] + side * (inner + outer) / 2, outer - inner
        c[o], s[o] = centre[o] + dy, rules.finger[1]
        c[2], s[2] = (z0 + z1) / 2, z1 - z0
        boxes.append((tuple(c), tuple(s)))
    return boxes


def blocker(focus: str, centre: Vec, dy: float, rules: CommandRules,
            model: EnvModel) -> str | None:
    """The first object a jaw would hit when gripping ``focus`` at ``centre``, if any."""
    moving = {focus, *model.supported_by(focus)}
    size = model.bodies[focus].size
    grow = 2 * rules.jaw_clearance
    for c, s in jaw_regions(centre, size, dy, rules):
        s = (s[0] + grow, s[1] + grow, s[2])  # keep the gap sideways only
        for name, b in model.bodies.items():
            if name not in moving and overlap(c, s, b.position, b.size, tol=0.5):
                return name
    return None


def choose_offset(focus: str, centre: Vec, rules: CommandRules,
                  model: EnvModel) -> tuple[float, str | None]:
    """The grip offset nearest the centre with free jaws, or (0, what blocks the centre)."""
    size = model.bodies[focus].size
    reach = max(0.0, (size[1 - rules.jaw_axis] - rules.finger[1]) / 2)
    first = blocker(focus, centre, 0.0, rules, model)
    if first is None:
        return 0.0, None
    k = 1
    while k * STEP_MM <= reach + 1e-9:
        for dy in (k * STEP_MM, -k * STEP_MM):
            if blocker(focus, centre, dy, rules, model) is None:
                return dy, None
        k += 1
    return 0.0, first
