"""An order for a ``$parallel``'s branches in which every one can be done (tracing.py).

A ``$parallel`` orders nothing (Fig. 17), but the first branch that can be done may
leave no room for a later one: three 12 mm cubes in a row 6 mm apart, the middle one
put last between the other two, leave no jaw room for it either way (bench 1086 and
1158 at 4x; the demonstration put the middle one first). The search is depth first,
the listed order first, and bounded.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

State = TypeVar("State")

SEARCH_TRIALS = 60  # branch attempts one search may make


def feasible_order(state: State, count: int, attempt: Callable[[State, int], State | None],
                   trials: int = SEARCH_TRIALS) -> list[int] | None:
    """Indices ``0 .. count-1`` in an order in which ``attempt`` (the state after branch
    ``i`` is done from ``state``, or None if it cannot be) succeeds for every branch;
    None if no such order was found within ``trials`` attempts."""
    budget = [trials]

    def search(current: State, left: list[int]) -> list[int] | None:
        if not left:
            return []
        for i in left:
            if budget[0] <= 0:
                return None
            budget[0] -= 1
            after = attempt(current, i)
            if after is None:
                continue
            rest = search(after, [j for j in left if j != i])
            if rest is not None:
                return [i, *rest]
        return None

    return search(state, list(range(count)))
