"""The fine motion of a place (Sec. V-B5 ALIGN, Sec. IX-C1): set down clear, slide into contact.

A place is made one of three ways (commands.yaml ``fine-motion``):

| kind  | when                                  | how                                   |
|-------|---------------------------------------|---------------------------------------|
| plain | the jaws are clear at the goal        | straight down, let go (Table IX PLACE)|
| slide | the demonstration aligned the block   | set down ``clearance`` mm from the    |
|       | (SC+ holds a fine-motion relation), or| partner, slide into contact holding   |
|       | a block is within ``snap-gap`` on one | it, let go                            |
|       | side; the contact lies across the jaws|                                       |
| push  | a jaw's own side is in contact at the | set down where the jaws are clear,    |
|       | goal (the partner, or a neighbour no  | let go, push it in with the closed    |
|       | jaw can pass)                         | jaws                                  |

An aligned block's goal is where the demonstration's relation puts it: the
faces across the contact coplanar — the pair of faces the taught spot had
nearer to coplanar; the coplanar relation itself names no face (Sec. V-B5:
"the coplanar relation defines the relative orientation of the objects") —
and as far from the partner as taught, but never nearer than ``contact-gap``.
The distance is kept because the coplanar-detector does not see contact: a
block set down a few mm beside another with its faces in line reads as an
ALIGN too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lbw_engine.do import jaws
from lbw_engine.do.plan import Operator
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Box, Vec, overlap
from lbw_engine.rules.commands import CommandRules

FACES = {(0, -1): "west", (0, 1): "east", (1, -1): "south", (1, 1): "north"}
ROOM_LIMIT_MM = 60.0  # how far from its contact a block may be set down for a push


PUSH = "push"  # the place kind whose fine motion slides the released block with closed jaws


@dataclass(frozen=True)
class Alignment:
    """Faces of ``subject`` and ``partner`` coplanar along ``axis`` on ``side`` (-1 low, +1
    high), the two in contact across the other horizontal axis."""

    subject: str
    partner: str
    axis: int
    side: int
    gap: float = 0.0  # mm between the blocks across the contact, as taught

    @property
    def face(self) -> str:
        """The coplanar faces by the scenario format's names (design.md: north = +y)."""
        return FACES[(self.axis, self.side)]


@dataclass(frozen=True)
class PlacePlan:
    """How a place is made: its kind, the object's goal centre, and the fine motion's points."""

    kind: str  # "plain" | "slide" | "push"
    goal: Vec
    set_down: Vec | None = None  # object centre where it is set down (slide, push)
    push_from: Vec | None = None  # tool point where the closed jaws come down (push)
    push_to: Vec | None = None  # tool point where they stop
    alignment: Alignment | None = None


def aligned(op: Operator, focus: str, goal: Vec, rules: CommandRules,
            model: EnvModel) -> tuple[Vec, Alignment] | None:
    """The goal aligned with the object the operator's SC+ relates ``focus`` to by a
    fine-motion relation, or None: no such relation, or that object is not beside the
    goal now (not yet where the demonstration had it, e.g. in a replanned order)."""
    for r in op.sc_plus:
        if r.type not in rules.fine.relations or r.subject != focus:
            continue
        for other in r.objects:
            if other in model.bodies and other != focus:
                found = align_goal(focus, goal, other, rules, model)
                if found is not None:
                    return found
    return None


def align_goal(focus: str, goal: Vec, other: str, rules: CommandRules,
               model: EnvModel) -> tuple[Vec, Alignment] | None:
    """The taught goal made flush with one face of ``other``, at the taught distance
    from it across the contact (at least ``contact-gap``: never into it); None when
    the goal is not within ``clearance`` of ``other`` on both counts, or when the
    flush spot would run into a third object (the taught spot then stands)."""
    size, p = model.bodies[focus].size, model.bodies[other]
    gaps = [abs(goal[k] - p.position[k]) - (size[k] + p.size[k]) / 2 for k in range(2)]
    contact = 0 if gaps[0] >= gaps[1] else 1  # the axis along which they are apart
    flush = 1 - contact
    gap = max(gaps[contact], rules.fine.contact_gap)
    out = list(goal)
    side = 1.0 if goal[contact] >= p.position[contact] else -1.0
    out[contact] = p.position[contact] + side * ((size[contact] + p.size[contact]) / 2 + gap)
    faces = []
    for s in (-1, 1):  # which pair of faces across the contact the taught spot had flush
        want = p.position[flush] + s * (p.size[flush] - size[flush]) / 2
        faces.append((abs(goal[flush] - want), s, want))
    off, s, out[flush] = min(faces)
    spot = (out[0], out[1], out[2])
    if gaps[contact] > rules.fine.clearance or off > rules.fine.clearance or \
            not _free(focus, spot, model):
        return None
    return spot, Alignment(focus, other, flush, s, gap)


def plan_place(focus: str, goal: Vec, axis: int, offset: float, rules: CommandRules,
               model: EnvModel, alignment: Alignment | None = None) -> tuple[PlacePlan | None, str]:
    """How to put the held ``focus`` (gripped along ``axis``) at ``goal``; or None and why."""
    if alignment is not None:
        contact = 1 - alignment.axis
        toward = 1 if model.bodies[alignment.partner].position[contact] > goal[contact] else -1
        if axis != contact:
            plan = _slide(focus, goal, axis, offset, contact, toward, rules, model)
        else:
            plan = _push(focus, goal, axis, offset, toward, rules, model, aligned=True)
        if plan is not None:
            return PlacePlan(plan.kind, goal, plan.set_down, plan.push_from, plan.push_to,
                             alignment), ""
    hit = jaws.blocker(focus, goal, axis, offset, rules, model)
    if hit is None:
        near = _near_sides(focus, goal, 1 - axis, rules, model)
        if alignment is None and len(near) == 1:  # a face to meet across the jaws: slide in
            plan = _slide(focus, goal, axis, offset, 1 - axis, near[0], rules, model)
            if plan is not None:
                return plan, ""
        return PlacePlan("plain", goal, alignment=alignment), ""
    blocked = _blocked_sides(focus, goal, axis, offset, rules, model)
    if len(blocked) == 1:
        plan = _push(focus, goal, axis, offset, blocked[0], rules, model,
                     aligned=alignment is not None)
        if plan is not None:
            return plan, ""
    return None, (f"a jaw would hit '{hit}' at {_mm(model.bodies[hit].position)}, and there "
                  "is no room to set it down clear and push it in")


def _near_sides(focus: str, goal: Vec, k: int, rules: CommandRules,
                model: EnvModel) -> list[int]:
    """The sides (-1, +1 along ``k``) where a block beside the goal, level with it, is
    nearer than ``fine-motion.snap-gap``: set straight down, a measurement error would put
    the two into each other."""
    return sorted(side for side, gap in _side_gaps(focus, goal, k, model).items()
                  if gap < rules.fine.snap_gap)


def _side_gaps(focus: str, goal: Vec, k: int, model: EnvModel) -> dict[int, float]:
    """The gap (mm) to the nearest block beside the goal on each side (-1, +1) along ``k``,
    of those level with it and facing it across ``k``."""
    size = model.bodies[focus].size
    ignore = jaws.moving(focus, model)
    o = 1 - k
    gaps: dict[int, float] = {}
    for name, b in model.bodies.items():
        level = (size[2] + b.size[2]) / 2 - abs(goal[2] - b.position[2]) > 0.5
        beside = (size[o] + b.size[o]) / 2 - abs(goal[o] - b.position[o]) > 0.5
        if name in ignore or not (level and beside):
            continue
        side = 1 if b.position[k] > goal[k] else -1
        gap = abs(goal[k] - b.position[k]) - (size[k] + b.size[k]) / 2
        gaps[side] = min(gap, gaps.get(side, math.inf))
    return gaps


def _blocked_sides(focus: str, goal: Vec, axis: int, offset: float, rules: CommandRules,
                   model: EnvModel) -> list[int]:
    """The jaw sides (-1, +1 along ``axis``) whose finger region holds another object."""
    regions = jaws.jaw_regions(goal, model.bodies[focus].size, axis, offset, rules)
    ignore = jaws.moving(focus, model)
    return [side for side, box in zip((-1, 1), regions, strict=True)
            if jaws.hit([box], model, ignore, 2 * rules.jaw_clearance) is not None]


def _shifted(p: Vec, axis: int, d: float) -> Vec:
    """``p`` moved by ``d`` along ``axis``."""
    q = list(p)
    q[axis] += d
    return (q[0], q[1], q[2])


def _free(focus: str, centre: Vec, model: EnvModel) -> bool:
    """Does the object (and what rides on it) fit at ``centre`` without meeting anything?"""
    size = model.bodies[focus].size
    ignore = jaws.moving(focus, model)
    return all(not overlap(centre, size, b.position, b.size, tol=0.0)
               for n, b in model.bodies.items() if n not in ignore)


def _slide(focus: str, goal: Vec, axis: int, offset: float, contact: int, toward: int,
           rules: CommandRules, model: EnvModel) -> PlacePlan | None:
    """Set down ``clearance`` away from the contact, slide in holding it (jaws across)."""
    spot = _shifted(goal, contact, -toward * rules.fine.clearance)
    size = model.bodies[focus].size
    swept = [_union(a, b) for a, b in zip(jaws.jaw_regions(spot, size, axis, offset, rules),
                                          jaws.jaw_regions(goal, size, axis, offset, rules),
                                          strict=True)]
    if not _free(focus, spot, model) or \
            jaws.hit(swept, model, jaws.moving(focus, model), 2 * rules.jaw_clearance):
        return None
    return PlacePlan("slide", goal, spot)


def _push(focus: str, goal: Vec, axis: int, offset: float, toward: int,
          rules: CommandRules, model: EnvModel, aligned: bool = False) -> PlacePlan | None:
    """Set down clear of the contact at ``toward`` (along the jaws), let go, push it in;
    ``aligned``: its faces must end coplanar with a neighbour's (it keeps its goal)."""
    size = model.bodies[focus].size
    ignore = jaws.moving(focus, model)
    if not aligned:
        goal = _clear_across(focus, goal, 1 - axis, rules, model)
    room = rules.fine.clearance
    while room <= ROOM_LIMIT_MM:
        spot = _shifted(goal, axis, -toward * room)
        if _free(focus, spot, model) and \
                jaws.blocker(focus, spot, axis, offset, rules, model) is None:
            # A push needs the closed fingers on part of the face only: beside a
            # neighbour they may meet it off centre (a small block in a corner).
            for shift in jaws.steps_within(size[1 - axis] / 2):
                start, end = _pusher(_shifted(spot, 1 - axis, shift), size, axis, toward,
                                     room, rules)
                boxes = [_closed_jaws(p, axis, rules) for p in (start, end)]
                if jaws.hit(boxes, model, ignore, 2 * rules.jaw_clearance) is None:
                    return PlacePlan(PUSH, goal, spot, start, end)
        room += jaws.STEP_MM
    return None


def _clear_across(focus: str, goal: Vec, k: int, rules: CommandRules, model: EnvModel) -> Vec:
    """``goal`` moved along ``k`` (across a push) to ``snap-gap`` from a block beside it on
    that axis, when there is one on one side only. The block is let go on the table and
    slid along the other axis: set down flush with a neighbour, a measurement error of 1
    mm put it on that neighbour's edge, it fell off tilted, and the closed jaws came down
    on it and flung it 200 mm (helper round 10, v06c: the last cube of a 2x2 grid
    touching, pushed into its corner)."""
    gaps = _side_gaps(focus, goal, k, model)
    near = [side for side, gap in gaps.items() if gap < rules.fine.snap_gap]
    if len(near) != 1 or gaps.get(-near[0], math.inf) < 2 * rules.fine.snap_gap:
        return goal  # clear already, or no room to step away
    return _shifted(goal, k, -near[0] * (rules.fine.snap_gap - gaps[near[0]]))


def _pusher(spot: Vec, size: Vec, axis: int, toward: int, room: float,
            rules: CommandRules) -> tuple[Vec, Vec]:
    """Tool points of the closed jaws: behind the set-down block, then ``room`` further on.

    The closed fingers, 2 × thickness along the jaws, start ``gripper.clearance``
    behind the block's far face with their tips ``tip-clearance`` above its bottom.
    """
    back = spot[axis] - toward * (size[axis] / 2 + rules.finger[0] + rules.jaw_clearance)
    z = spot[2] - size[2] / 2 + rules.tip_clearance + rules.tip
    start = [spot[0], spot[1], z]
    start[axis] = back
    end = _shifted((start[0], start[1], start[2]), axis, toward * (room + rules.jaw_clearance))
    return (start[0], start[1], start[2]), end


def _closed_jaws(tool: Vec, axis: int, rules: CommandRules) -> Box:
    """The box the closed fingers fill, from their tips up past the approach height."""
    t = rules.finger[0]
    return jaws.column(tool, (tool[axis] - t, tool[axis] + t), axis, rules.finger[1], tool[2],
                       rules)


def _union(a: Box, b: Box) -> Box:
    """The smallest box holding two boxes."""
    lo = [min(a[0][k] - a[1][k] / 2, b[0][k] - b[1][k] / 2) for k in range(3)]
    hi = [max(a[0][k] + a[1][k] / 2, b[0][k] + b[1][k] / 2) for k in range(3)]
    return (tuple((lo[k] + hi[k]) / 2 for k in range(3)), tuple(hi[k] - lo[k] for k in range(3)))


def _mm(v: Vec) -> str:
    """A position for messages."""
    return "(" + ", ".join(f"{c:.0f}" for c in v) + ") mm"


def coplanar_errors(alignment: Alignment, positions: dict[str, Vec],
                    sizes: dict[str, Vec]) -> tuple[float, float]:
    """How far the aligned faces are from coplanar, and the gap across the contact (mm)."""
    a, b = alignment.subject, alignment.partner
    k, s = alignment.axis, alignment.side
    face = abs((positions[a][k] + s * sizes[a][k] / 2) - (positions[b][k] + s * sizes[b][k] / 2))
    c = 1 - k
    gap = abs(positions[a][c] - positions[b][c]) - (sizes[a][c] + sizes[b][c]) / 2
    return face, gap
