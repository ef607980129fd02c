"""How a measured block lies: upright, on a side, or turned part way over (issue #13).

The monitor's looks measure boxes; a plan object whose box has its shape's extents in
another order has fallen over, and the robot's grasps, which keep a block's
orientation, cannot stand it up again (lbw_engine.pipeline.monitor names it and
ends the run). Pure geometry on measured extents.
"""

from __future__ import annotations

import math
from itertools import permutations
from typing import Any

TOPPLED_MM = 12.0  # a block seen this far off its shape's extents has fallen over
# a block on the table (bottom within ON_TABLE_MM of it) fits lying on a side this much
# better than upright, its height this far off: it has fallen over (``tipped``)
TIPPED_MM, ON_TABLE_MM = 6.0, 4.0


def on_side(size: Any, want: Any) -> bool:
    """Extents that are the shape's in another order (within the tolerance), not upright."""
    same = all(abs(a - b) <= TOPPLED_MM for a, b in zip(sorted(size), sorted(want), strict=True))
    return same and max(abs(size[k] - want[k]) for k in (0, 1)) > TOPPLED_MM


def tilted(size: Any, want: Any) -> bool:
    """Extents of the shape turned part way over in the x-z plane (as pymunk turns
    blocks): its y extent kept, x and z those of a turned L x H rectangle (a plank leaning
    on a pillar, seen 139 x 32 x 80 for 160 x 30 x 15)."""
    if abs(size[1] - want[1]) > TOPPLED_MM:
        return False
    length, height = want[0], want[2]
    upright = abs(size[0] - length) + abs(size[2] - height)
    # half a radian or more from upright and from lying (``_on_side``): a block turned
    # less reads within a misreading of either (a cube read 45 x 40 x 47 fitted 0.2 rad)
    for a in (0.5 + k * (math.pi / 2 - 1.0) / 20 for k in range(21)):
        dx = abs(size[0] - (length * math.cos(a) + height * math.sin(a)))
        dz = abs(size[2] - (length * math.sin(a) + height * math.cos(a)))
        if max(dx, dz) <= TOPPLED_MM and dx + dz + TIPPED_MM < upright:
            return True
    return False


def tipped(position: Any, size: Any, want: Any) -> bool:
    """A block on the table whose three extents are its shape's with another axis upright,
    clearly better than upright (helper round 5, t35: a 20 x 70 x 30 block on its side,
    seen 30 x 70 x 20, is off by 10 mm per axis, under TOPPLED_MM)."""
    if position[2] - size[2] / 2.0 > ON_TABLE_MM or abs(size[2] - want[2]) <= TIPPED_MM:
        return False
    upright = sum(abs(a - b) for a, b in zip(size, want, strict=True))
    lying, worst = min(((sum(d), max(d)) for p in permutations(want) if p[2] != want[2]
                        for d in [[abs(a - b) for a, b in zip(size, p, strict=True)]]),
                       default=(math.inf, math.inf))
    # and the lying reading must fit on each axis: a plank read 42 x 30 x 46 (three
    # blocks' columns merged) fits lying "better" than upright, and fits neither (AL)
    return lying + TIPPED_MM < upright and worst <= TOPPLED_MM  # a cube: never


def dims(size: Any) -> str:
    """A size for messages."""
    return " x ".join(f"{v:.0f}" for v in size)
