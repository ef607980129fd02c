"""Room for the gripper's jaws: which way they close and where they grip, clear of neighbours.

The paper grips every object at its centre (Sec. VII-B) and names the lack of
a grasp planner as a limitation (Sec. IX-B). Here the wrist turns about the
vertical axis (design.md "Robot"), so the jaws close along world x or y, and
the grip point may slide along the object across the jaws, to the first offset
whose jaw regions are free. A jaw region spans from the object's side to the
open finger's outer face, and from the fingertips up to above the approach
height; the held object and what rides on it are not obstacles. A gap of
``gripper.clearance`` is kept sideways, since positions are measured by the
cameras.
"""

from __future__ import annotations

from collections.abc import Iterable

from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Box, Vec, overlap, within_along
from lbw_engine.rules.commands import CommandRules

STEP_MM = 5.0  # spacing of candidate grip offsets
AXIS_NAMES = ("x", "y")
RIDER_SLACK_MM = 3.0  # a rider measured within this past the block it rides on is as wide


def width(size: Vec, axis: int, rules: CommandRules) -> float | None:
    """The jaw opening that takes an object of ``size`` along ``axis``; None if too wide."""
    w = size[axis] + rules.margin
    return w if w <= rules.max_opening + 1e-9 else None


def fitting_axes(size: Vec, rules: CommandRules) -> list[int]:
    """The jaw axes whose opening takes an object of ``size`` (``width``)."""
    return [a for a in rules.jaw_axes if width(size, a, rules) is not None]


def too_wide(name: str, size: Vec, rules: CommandRules) -> str:
    """Why no jaw axis takes ``name`` (``fitting_axes`` empty)."""
    return (f"'{name}' is {describe(size)} across, wider than the jaws open "
            f"({rules.max_opening:g} mm with {rules.margin:g} mm to spare) whichever way "
            "they close")


def unmovable(names: Iterable[str], rules: CommandRules, model: EnvModel) -> str | None:
    """Why the robot cannot do a plan that puts ``names`` somewhere: the first of them (in
    the model) that no jaw axis takes; None when every one fits."""
    for name in names:
        body = model.bodies.get(name)
        if body is not None and not fitting_axes(body.size, rules):
            return too_wide(name, body.size, rules) + ", and the plan moves it"
    return None


def tool_point(centre: Vec, size: Vec, axis: int, offset: float, rules: CommandRules) -> Vec:
    """Where the arm's tool point goes to grip an object centred at ``centre``."""
    p = [centre[0], centre[1], centre[2] + rules.grip_offset(size)]
    p[1 - axis] += offset
    return (p[0], p[1], p[2])


def column(centre: Vec, extent: tuple[float, float], axis: int, across: float,
           grip_z: float, rules: CommandRules) -> Box:
    """A finger-like box: ``extent`` along ``axis``, ``across`` wide on the other horizontal
    axis around ``centre``, from the fingertips (tool point at ``grip_z``) up past the
    approach height.

    It reaches ``tip-clearance`` below the fingertips: a neighbour whose top is level
    with them would be rubbed by the closing fingers (and dragged along: found on a
    60 mm brick gripped beside a 20 mm plank, whose top the fingertips just met).
    """
    z0 = grip_z - rules.tip - rules.tip_clearance
    z1 = max(grip_z, rules.approach_height) - rules.tip + rules.finger[2]
    c, s = [0.0, 0.0, (z0 + z1) / 2], [0.0, 0.0, z1 - z0]
    c[axis], s[axis] = (extent[0] + extent[1]) / 2, extent[1] - extent[0]
    c[1 - axis], s[1 - axis] = centre[1 - axis], across
    return (c[0], c[1], c[2]), (s[0], s[1], s[2])


def jaw_regions(centre: Vec, size: Vec, axis: int, offset: float,
                rules: CommandRules) -> list[Box]:
    """The two boxes the open fingers sweep when gripping an object at ``centre``."""
    inner = size[axis] / 2
    outer = (size[axis] + rules.margin) / 2 + rules.finger[0]
    mid = list(centre)
    mid[1 - axis] += offset
    grip_z = centre[2] + rules.grip_offset(size)
    return [column((mid[0], mid[1], mid[2]),
                   tuple(sorted((centre[axis] + side * inner, centre[axis] + side * outer))),
                   axis, rules.finger[1], grip_z, rules)
            for side in (-1, 1)]


def hit(boxes: Iterable[Box], model: EnvModel, ignore: set[str],
        grow: float = 0.0) -> str | None:
    """The first object (not in ``ignore``) that one of ``boxes``, grown sideways, meets."""
    for c, s in boxes:
        s = (s[0] + grow, s[1] + grow, s[2])  # keep the gap sideways only
        for name, b in model.bodies.items():
            if name not in ignore and overlap(c, s, b.position, b.size, tol=0.5):
                return name
    return None


def moving(focus: str, model: EnvModel) -> set[str]:
    """The object and what rides on it: they move with the jaws, never in their way."""
    return {focus, *model.supported_by(focus)}


def blocker(focus: str, centre: Vec, axis: int, offset: float, rules: CommandRules,
            model: EnvModel) -> str | None:
    """The first object a jaw would hit when gripping ``focus`` at ``centre``, if any.

    A rider that reaches past ``focus`` along the jaw axis is in the way: the jaws meet
    it first (a 40 x 30 block on a 30 x 40 one, gripped along x: the jaws held the
    rider, round 14, v48v). Measured, an equal rider may reach RIDER_SLACK_MM past it (at
    pixel 4 the equal cube on a cube did, and the grip was refused: v48w)."""
    f = model.bodies[focus]
    inside = {n for n in moving(focus, model) if within_along(
        model.bodies[n].position, model.bodies[n].size, f.position, f.size, axis,
        RIDER_SLACK_MM)}
    return hit(jaw_regions(centre, f.size, axis, offset, rules), model, inside,
               2 * rules.jaw_clearance)


def offsets(size: Vec, axis: int, rules: CommandRules) -> list[float]:
    """Candidate grip offsets across the jaws, nearest the centre first (5 mm apart).

    Nearest first, the fingers grip over the whole of the narrower of the finger and
    the face: a face wider than the finger lets it slide along the face, a face
    narrower than the finger (a 12 mm cube, 20 mm deep fingers) lets the finger stick
    out on one side only, away from a neighbour. Farther out, in 5 mm steps, a finger
    sticks out past the face until it grips half of the narrower of the two: against
    a neighbour touching that side (measured even 1 mm into it), it must end
    ``clearance`` inside the face. 15 mm cubes set against each other along x could
    be gripped neither way (lbw bench 1050, with execution objects in side contact).
    """
    spare = abs(size[1 - axis] - rules.finger[1]) / 2
    farther = steps_within(max(size[1 - axis], rules.finger[1]) / 2)
    return steps_within(spare) + [o for o in farther if abs(o) > spare + 1e-9]


def steps_within(reach: float) -> list[float]:
    """0, ±5, ±10 ... mm up to ``reach``, and ±``reach`` itself (a 12 mm cube: 0, ±4)."""
    out, k = [0.0], 1
    while k * STEP_MM <= reach + 1e-9:
        out += [k * STEP_MM, -k * STEP_MM]
        k += 1
    if reach > (k - 1) * STEP_MM + 0.5:
        out += [reach, -reach]
    return out


def describe(size: Vec) -> str:
    """An object's footprint for messages."""
    return f"{size[0]:g} × {size[1]:g} mm"
