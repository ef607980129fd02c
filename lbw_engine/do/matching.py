"""Initial-state matching between teaching and execution (Sec. VII-A, steps 1–5).

Pure data in, data out: the taught objects, the objects the plan's root uses,
and the objects the object-finder measured in the execution workspace. The
match goes in two stages with the shape name as the key — measured objects →
the plan's object list → the taught environment model — so irrelevant objects
drop out on both sides, and among objects of equal shape the first measured
one goes to the first listed plan object (first come, first served).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from lbw_engine.do.plan import Plan
from lbw_engine.errors import TaskFailed

# The table and the hand are instantiated from calibration, never matched (Sec. VII-A 5).
NOT_MATCHED = frozenset({"table", "hand"})


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
    """The objects the plan's root uses (base, target, special; Sec. VII-A 2), in order."""
    root = plan.operators[plan.root]
    out: list[str] = []
    for slot in ("base", "target", "special"):
        for name in root.slots[slot]:
            if name not in NOT_MATCHED and name not in out:
                out.append(name)
    return out


def taught_shapes(plan: Plan, teach_objects: Mapping[str, Mapping]) -> dict[str, dict]:
    """Taught objects {name: {shape, position}}: plan.json's objects, else the scenario's."""
    return dict(plan.objects) if plan.objects is not None else dict(teach_objects)


def match_initial_state(
    taught: Mapping[str, Mapping],
    relevant: Sequence[str],
    measured: Sequence[Measured],
) -> Matching:
    """Match the plan's objects to measured ones by shape, first come first served.

    Raises TaskFailed naming the first plan object whose shape has no
    (remaining) measured object.
    """
    pool: dict[str, list[int]] = {}  # shape -> measured indices, in measured order
    for i, m in enumerate(measured):
        pool.setdefault(m.shape, []).append(i)
    assigned: dict[str, int] = {}
    for name in relevant:
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
        assigned[name] = free.pop(0)
    used = set(assigned.values())
    return Matching(
        positions={n: tuple(measured[i].position) for n, i in assigned.items()},
        assigned=assigned,
        unmatched=[i for i in range(len(measured)) if i not in used],
    )
