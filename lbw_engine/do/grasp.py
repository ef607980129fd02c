"""Which way the jaws close on an object, chosen for the whole hold: where it is picked up
and where it is put down (design.md "Robot": the wrist turns about the vertical axis).

A held block never turns (boxes stay axis-aligned), so the wrist's turn and the
grip offset chosen at the pick serve the place too. The candidates are the
`gripper.jaw-axes` in their listed order whose opening fits (`max-opening`),
each with its grip offsets nearest the centre first (jaws.py). A candidate
must leave the jaws clear at the pick; among those, the first whose place can
be made straight down or with a held slide wins, else the first whose place
needs the push (fine.py). When some ways serve the pick and others the place,
but none both, ``NoCommonGrip`` says so: the object is put down on the way and
taken again the other way (a regrasp, clearing.py). Else the grip is refused
(``Blocked``), naming what is in the way: the caller may set that aside first
(setaside.free_grasp). Without a place ahead (a touch), the pick decides.
"""

from __future__ import annotations

from collections.abc import Callable

from lbw_engine.do import jaws
from lbw_engine.do.fine import PlacePlan
from lbw_engine.errors import TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Vec
from lbw_engine.rules.commands import CommandRules

# (axis, offset) -> how the coming place would be made, or (None, why); None: no place ahead
PlaceAhead = Callable[[int, float], tuple[PlacePlan | None, str] | None]
Grip = tuple[int, float]  # jaw axis (0: x, 1: y), grip offset across the jaws (mm)


class Blocked(TaskFailed):
    """No way of gripping the object leaves the jaws clear: ``hits``, per jaw axis, the
    first object in the way."""

    def __init__(self, message: str, hits: dict[int, str]) -> None:
        super().__init__(message)
        self.hits = hits


class NoCommonGrip(TaskFailed):
    """Some grips serve the pick, others the place, none both."""

    def __init__(self, message: str, picks: list[Grip], places: list[Grip]) -> None:
        super().__init__(message)
        self.picks, self.places = picks, places


def choose(focus: str, centre: Vec, rules: CommandRules, model: EnvModel,
           place: PlaceAhead | None = None, strict: bool = True) -> tuple[int, float]:
    """The jaw axis and grip offset for picking ``focus`` at ``centre``.

    Raises TaskFailed (when ``strict``) if no way of gripping it works; otherwise
    falls back to the first way the jaws fit.
    """
    size = model.bodies[focus].size
    fits = jaws.fitting_axes(size, rules)
    if not fits:
        if strict:
            raise TaskFailed(jaws.too_wide(focus, size, rules))
        return rules.jaw_axes[0], 0.0
    pushed: Grip | None = None
    picks: list[Grip] = []
    pick_hits: dict[int, str] = {}  # jaw axis -> the first object in the way
    place_why = None
    for axis in fits:
        for off in jaws.offsets(size, axis, rules):
            hit = jaws.blocker(focus, centre, axis, off, rules, model)
            if hit is not None:
                pick_hits.setdefault(axis, hit)
                continue
            picks.append((axis, off))
            ahead = place(axis, off) if place is not None else None
            if ahead is None or (ahead[0] is not None and ahead[0].kind != "push"):
                return axis, off
            if ahead[0] is not None:
                pushed = pushed or (axis, off)
            else:
                place_why = place_why or ahead[1]
    if pushed is not None:
        return pushed
    if not strict:
        return fits[0], 0.0
    if place_why is not None:
        places = [(a, o) for a in fits for o in jaws.offsets(size, a, rules)
                  if (place(a, o) or (None, ""))[0] is not None]
        message = (f"'{focus}' can be picked up but not put down where the plan wants it, "
                   f"whichever way the jaws close: {place_why}")
        if places:
            raise NoCommonGrip(message, picks, places)
        raise TaskFailed(message)
    if len(set(pick_hits.values())) == 1:
        name = next(iter(pick_hits.values()))
        where = f"'{name}' at {_mm(model.bodies[name].position)} whichever way the jaws close"
    else:  # each way has its own obstacle: name both
        where = ", and ".join(f"'{n}' at {_mm(model.bodies[n].position)} closing along "
                              f"{jaws.AXIS_NAMES[a]}" for a, n in pick_hits.items())
    raise Blocked(f"the gripper cannot hold '{focus}' at {_mm(centre)}: a jaw would hit "
                  f"{where}", pick_hits)


def _mm(v: Vec) -> str:
    """A position for messages."""
    return "(" + ", ".join(f"{c:.0f}" for c in v) + ") mm"
