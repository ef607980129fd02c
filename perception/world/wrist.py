"""Which way the demonstrator's fingers close for each hold: the person turns the wrist too.

A person picking a block out of a row along x takes it across y, so their
fingers never go between the block and its neighbour. The hand
(``perception.world.hand``) closes along x (axis 0) or y (axis 1); this picks
the axis for each pick or touch from the scenario's own layouts (the person
sees the world; perception does not get this), so that the fingers have room
at the pick, at the place that follows, and along an ALIGN slide (Sec. V-B5)
in between. x wins when both are free, so demonstrations that never needed
the turn are unchanged, unless the block is too long along x for a comfortable
grip (COMFORTABLE_SPAN) and its y side is free.

Why not the robot's free-side test (``lbw_engine.do.jaws.blocker``)? The
layers would allow the import, but that test is parametrised by the robot's
gripper (rules/commands.yaml: its finger, margin, jaw clearance, approach
height) over a perceived EnvModel, and it slides the grip off-centre. The
hand has its own fingers, pre-shape clearance and grip height (hand.py) and
always grips at the centre, so reusing it would mean forging robot command
rules for the person; the test below is the hand's own, in a few lines.
"""

from __future__ import annotations

from collections.abc import Sequence

from lbw_engine.model.geometry import within_along
from perception.world.hand import CLEARANCE, TIP, GripperGeometry, grasp_offset
from perception.world.layout import Layout, box_bounds, overlaps

Vec3 = tuple[float, float, float]

SLACK = 2.0  # mm beyond the open finger's outer face: tremor and the slanted approach
CONTACT_GAP = 0.3  # mm left between blocks after an align slide toward another block
SLIDE_STEP = 2.0  # mm between the points checked along an align slide
HAND = GripperGeometry()
# A person takes a beam longer than the hand's span across its width, not between its
# ends: a pre-shape wider than this is used only when the narrow side has no room (a
# 180 mm beam held at its ends put the fingers 204 mm apart, too far for the
# hand-tracker's windows, Sec. V-A; a 160 mm plank, 184 mm, is still held lengthwise).
COMFORTABLE_SPAN = 190.0


def finger_boxes(center: Vec3, size: Vec3, axis: int) -> list[tuple]:
    """Bounds swept by the two fingers gripping a block of ``size`` at ``center``.

    Along ``axis`` from the block's face to the open finger's outer face (pre-shape
    clearance plus the finger's thickness, and SLACK); across it the finger's depth
    (hand.py: x-closing fingers are ``finger[1]`` deep in y, y-closing ones as wide in
    x); in z from the fingertips up (the fingers come down from above).
    """
    reach = CLEARANCE + HAND.finger[0] + SLACK
    tip = center[2] + grasp_offset(size) - TIP
    out = []
    for side in (-1, 1):
        c, s = list(center), [0.0, 0.0, 0.0]
        c[axis] += side * (size[axis] + reach) / 2
        s[axis] = reach
        s[1 - axis] = HAND.finger[1]
        c[2], s[2] = tip + 500.0, 1000.0
        out.append(box_bounds(c, s))
    return out


def has_room(lay: Layout, name: str, center: Vec3, axis: int) -> bool:
    """Do the fingers fit beside ``name`` at ``center`` in ``lay`` (it and its riders aside)?

    A rider that reaches past the block along ``axis`` is in the fingers' way: they
    would meet it first (a 40 x 30 block on a 30 x 40 one, taken closing along x:
    the jaws held the rider, round 14, v48v)."""
    moving = {name, *(r for r in lay.riders(name) if within_along(
        lay.center[r], lay.size[r], lay.center[name], lay.size[name], axis, 0.5))}
    for box in finger_boxes(center, lay.size[name], axis):
        for other in lay.center:
            if other not in moving and overlaps(box, lay.bounds(other)):
                return False
    return True


def _path(points: Sequence[Vec3]) -> list[Vec3]:
    """The points of a polyline, SLIDE_STEP mm apart or closer."""
    out = [points[0]]
    for a, b in zip(points, points[1:], strict=False):
        n = max(1, int(max(abs(b[k] - a[k]) for k in range(3)) / SLIDE_STEP) + 1)
        out += [tuple(a[k] + (b[k] - a[k]) * i / n for k in range(3)) for i in range(1, n + 1)]
    return out


def slide_path(lay: Layout, step) -> list[Vec3]:
    """Align slide (Sec. V-B5): into contact with ``with``, then along it until coplanar."""
    final, dest = step.final, step.dest
    w = lay.center[step.align.with_]
    contact_axis = 0 if step.align.face in ("north", "south") else 1
    side = 1.0 if final[contact_axis] >= w[contact_axis] else -1.0
    touching = list(dest)
    touching[contact_axis] = final[contact_axis] + side * CONTACT_GAP
    last = list(final)
    last[contact_axis] = touching[contact_axis]
    return [tuple(touching), tuple(last)]


def hold_axis(scenario, i: int) -> int | None:
    """The closing axis for the pick (or touch) at demonstration step ``i``.

    The fingers need room where the block is taken and, for a pick, where the next
    place of it puts it down: at the set-down point, along the align slide (if any)
    and at the final centre. None: neither axis has room.
    """
    steps = scenario.demonstration
    before = scenario.states[i - 1] if i else scenario.teach.layout()
    step = steps[i]
    checks = [(before, before.center[step.obj])]
    if step.kind == "pick":
        j = next((k for k in range(i + 1, len(steps))
                  if steps[k].kind == "place" and steps[k].obj == step.obj), None)
        if j is not None:
            after, place = scenario.states[j], steps[j]
            slide = slide_path(after, place) if place.align is not None else []
            checks += [(after, p) for p in _path([place.dest, *slide, place.final])]
    return _first_with_room(before.size[step.obj], step.obj, checks)


def squeeze_axis(scenario, i: int) -> int | None:
    """For a hold with no room on either axis (``hold_axis`` None): the axis whose
    fingers have room where the block is taken, if one has (the fingers are soft for
    the whole hold, but only at the place do they need to be). Taken with the other
    axis from a cluster of 20 mm cubes 20 mm apart, the fingers stood half inside a
    neighbour, and the hand-tracker's grip came out 4 mm off: the place at the corner
    of a grid was read on the three cubes around it (helper round 12, v11d)."""
    before = scenario.states[i - 1] if i else scenario.teach.layout()
    obj = scenario.demonstration[i].obj
    return _first_with_room(before.size[obj], obj, [(before, before.center[obj])])


def _first_with_room(size: Vec3, obj: str, checks: list) -> int | None:
    """The first axis (x before y; the wide grip only if it must be) whose fingers fit
    the block and have room at every (layout, centre) of ``checks``."""
    for span in (COMFORTABLE_SPAN, HAND.max_opening):
        for axis in (0, 1):
            if size[axis] + 2 * CLEARANCE <= span and all(
                    has_room(lay, obj, c, axis) for lay, c in checks):
                return axis
    return None
