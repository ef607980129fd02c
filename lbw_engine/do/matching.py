"""Initial-state matching between teaching and execution (Sec. VII-A, steps 1–5).

Pure data in, data out: the taught objects, the objects the plan uses (its root's, then
those only an operator names),
and the objects the object-finder measured in the execution workspace. The
match goes in two stages with the shape name as the key — measured objects →
the plan's object list → the taught environment model — so irrelevant objects
drop out on both sides, and among objects of equal shape the first measured
one goes to the first listed plan object (first come, first served), except that
objects the plan never moves but needs in place go to the nearest one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Hashable, Mapping, Sequence
from dataclasses import dataclass, field

from lbw_engine.do.placement import taught_positions
from lbw_engine.do.plan import Plan, placed
from lbw_engine.errors import TaskFailed
from lbw_engine.model.geometry import footprints_meet
from lbw_engine.names import TABLE

# The table and the hand are instantiated from calibration, never matched (Sec. VII-A 5).
NOT_MATCHED = frozenset({"table", "hand"})
COVER_MM = 5.0  # an object whose bottom is this near another's top lies on it


@dataclass(frozen=True)
class Measured:
    """One object the object-finder reported: its shape, centre and size (mm)."""

    shape: str
    position: tuple[float, float, float]
    size: tuple[float, float, float]


@dataclass(frozen=True)
class Matching:
    """The result: plan object → measured object, and what was left over."""

    positions: dict[str, tuple[float, float, float]]
    assigned: dict[str, int]  # plan object -> index into the measured list
    unmatched: list[int] = field(default_factory=list)  # measured but irrelevant


def plan_objects(plan: Plan) -> list[str]:
    """The objects the plan uses (base, target, special; Sec. VII-A 2), in order: the
    root's, then those only its operators name. A block the demonstration set a cube on
    and took it off again is in no slot of the root, whose SC+ is the final state, but
    the ACHIEVE that puts the cube on it needs it (helper round 11, v22a: "the relation
    names 'bs', which is not a plan object")."""
    out: list[str] = []
    for op in [plan.operators[plan.root], *plan.operators.values()]:
        for slot in ("base", "target", "special"):
            for name in op.slots.get(slot, ()):
                if name not in NOT_MATCHED and name not in out:
                    out.append(name)
    return out


def anchors(plan: Plan, support: Collection[str]) -> dict[str, tuple[float, ...]]:
    """The plan's objects that no operator moves (none gives them a new ``support``
    relation), at the world positions its operators' invariant relations (SI) say they
    stood when taught; those whose position the plan does not record are left out."""
    moved = placed(plan, support)
    taught = taught_positions([r for op in plan.operators.values() for r in op.si], support)
    for op in plan.operators.values():  # ... or, at an operator's end, relative to a load
        for name, at in taught_positions(op.si, support, op.sc_plus).items():
            taught.setdefault(name, at)
    return {n: taught[n] for n in plan_objects(plan) if n not in moved and n in taught}


def resting(plan: Plan, support: Collection[str]) -> list[tuple[str, str]]:
    """(object, the plan object it rests on) where the taught start had one plan object
    on another: the root's SC- (start relations the task ends) and SI (relations it
    keeps, such as a rider carried along), in plan order."""
    root = plan.operators[plan.root]
    names = set(plan_objects(plan))
    return [(r.subject, o) for r in (*root.sc_minus, *root.si) if r.type in support
            and r.subject in names for o in r.objects if o in names]


def raised(plan: Plan, support: Collection[str]) -> set[str]:
    """Plan objects the taught start had resting on a block the plan never names (the top
    of a stack that stays where it is, helper round 17): not on the table, and not on a
    plan object (``resting``)."""
    root = plan.operators[plan.root]
    names = set(plan_objects(plan))
    return {r.subject for r in (*root.sc_minus, *root.si) if r.type in support
            and r.subject in names and any(o not in names and o != TABLE for o in r.objects)}


def taught_shapes(plan: Plan, teach_objects: Mapping[str, Mapping]) -> dict[str, dict]:
    """Taught objects {name: {shape, position}}: plan.json's objects, else the scenario's."""
    return dict(plan.objects) if plan.objects is not None else dict(teach_objects)


def match_initial_state(
    taught: Mapping[str, Mapping],
    relevant: Sequence[str],
    measured: Sequence[Measured],
    anchors: Mapping[str, Sequence[float]] | None = None,
    stacked: Sequence[tuple[str, str]] = (),
    raised: Collection[str] = (),
) -> Matching:
    """Match the plan's objects to measured ones by shape, first come first served.

    ``anchors``: where the plan needs some of its objects to be, for objects it never
    moves (the taught positions of supports that other objects are put beside or on in
    world coordinates). Each takes, nearest first, the measured object of its shape
    nearest that position: a user who leaves one cube of a row where it stood expects
    the row built on it, not on another cube of that shape lying elsewhere.
    ``stacked``: (object, support) pairs the taught start had (``resting``); a measured
    pair of their shapes, one lying on the other, goes to them before the rest are
    served: a base taught carrying a rider is matched to a block carrying one, not to
    the rider (generated 3107).
    ``raised``: objects taught on a block the plan never names (``raised``) take a measured
    object lying on another where there is one: the stack's top is where it stays.
    Raises TaskFailed naming the first plan object whose shape has no
    (remaining) measured object.
    """
    pool: dict[str, list[int]] = {}  # shape -> measured indices, in measured order
    for i, m in enumerate(measured):
        pool.setdefault(m.shape, []).append(i)
    assigned: dict[str, int] = {}
    lying = {i for i, m in enumerate(measured) if any(
        j != i and _lies_on(m, b) for j, b in enumerate(measured))}

    def fits(name: str, i: int) -> bool:  # a raised object takes a raised one, if any
        return name not in raised or i in lying or not (
            lying & set(pool.get(taught[name]["shape"], [])))

    # nearest in 3-D: a support taught on top of a stack takes the top of the stack there
    pairs = sorted((math.dist(at[:3], measured[i].position[:3]), name, i)
                   for name, at in (anchors or {}).items() if name in relevant
                   and name in taught for i in pool.get(taught[name]["shape"], [])
                   if fits(name, i))
    for _, name, i in pairs:
        if name not in assigned and i in pool[taught[name]["shape"]]:
            assigned[name] = i
            pool[taught[name]["shape"]].remove(i)
    # bottom pairs first, and a pair's lower block the measured one as many blocks up as
    # the taught one: three equal cubes taught stacked went in upside down (review)
    under = dict(stacked)
    depth = {n: _below(n, lambda k, _: under.get(k)) for p in stacked for n in p}
    level = [_below(i, lambda k, seen: next((j for j, m in enumerate(measured) if j not in seen
                                             and _lies_on(measured[k], m)), None))
             for i in range(len(measured))]
    for up, down in sorted(stacked, key=lambda p: depth.get(p[1], 0)):
        if up not in relevant or down not in relevant or up not in taught or \
                down not in taught:
            continue
        ups = [assigned[up]] if up in assigned else pool.get(taught[up]["shape"], [])
        downs = [assigned[down]] if down in assigned else pool.get(taught[down]["shape"], [])
        pairs = [(i, j) for j in downs for i in ups if i != j
                 and _lies_on(measured[i], measured[j])]
        if not pairs:
            continue
        pair = min(pairs, key=lambda p: abs(level[p[1]] - depth.get(down, 0)))
        for name, i in zip((up, down), pair, strict=True):
            if name not in assigned:
                assigned[name] = i
                pool[taught[name]["shape"]].remove(i)
    for name in sorted(relevant, key=lambda n: n not in raised):  # the raised ones first
        if name in assigned:
            continue
        if name not in taught:
            raise TaskFailed(f"the plan uses '{name}' but the taught workspace has no such object")
        shape = taught[name]["shape"]
        free = pool.get(shape, [])
        if not free:
            have = sum(1 for m in measured if m.shape == shape)
            want = sum(1 for n in relevant if n in taught and taught[n]["shape"] == shape)
            raise TaskFailed(
                f"object '{name}' (shape {shape}) has no counterpart in the execution "
                f"workspace: the plan needs {want} {shape}(s), the object-finder saw {have}"
            )
        # a block with another lying on it is taken only if no free one is left: the
        # robot would first have to set the other aside (a stack of equal blocks)
        pick = next((i for i in free if fits(name, i) and not _covered(i, measured)),
                    next((i for i in free if fits(name, i)), free[0]))
        free.remove(pick)
        assigned[name] = pick
    used = set(assigned.values())
    return Matching(
        positions={n: tuple(measured[i].position) for n, i in assigned.items()},
        assigned=assigned,
        unmatched=[i for i in range(len(measured)) if i not in used],
    )


def _below(start: Hashable, under: Callable[[Hashable, set], Hashable | None]) -> int:
    """How many blocks lie under ``start``, following ``under(block, seen)`` (the block it
    lies on, or None) down the stack; a cycle stops the count. Taught names and measured
    indices alike."""
    k, seen = start, {start}
    while (j := under(k, seen)) is not None and j not in seen:
        k = j
        seen.add(j)
    return len(seen) - 1


def _lies_on(b: Measured, a: Measured) -> bool:
    """Whether measured ``b``'s bottom is on measured ``a``'s top, their footprints met."""
    top = a.position[2] + a.size[2] / 2
    return abs(b.position[2] - b.size[2] / 2 - top) <= COVER_MM and \
        footprints_meet(a.position, a.size, b.position, b.size, tol=0.0)


def _covered(i: int, measured: Sequence[Measured]) -> bool:
    """Whether another measured object lies on measured object ``i``."""
    return any(j != i and _lies_on(b, measured[i]) for j, b in enumerate(measured))
