"""Table IV: qualitative motion feature values from the hand's 3-D velocity."""

from __future__ import annotations

import math
from collections.abc import Sequence

from lbw_engine.rules import MotionFeatures


def speed_class(speed: float, low: float, high: float) -> str:
    """``slow`` below the lower threshold, ``fast`` above the higher, else ``within``."""
    if speed < low:
        return "slow"
    if speed > high:
        return "fast"
    return "within"


def down_angle(velocity: Sequence[float]) -> float | None:
    """Degrees between ``velocity`` and straight down (footnote 11); None when at rest."""
    vx, vy, vz = (float(c) for c in velocity)
    norm = math.sqrt(vx * vx + vy * vy + vz * vz)
    if norm == 0.0:
        return None
    return math.degrees(math.acos(max(-1.0, min(1.0, -vz / norm))))


def direction_class(velocity: Sequence[float], down: float, up: float) -> str:
    """Angle from straight down (footnote 11): <= A_D down, >= A_U up, else lateral."""
    angle = down_angle(velocity)
    if angle is None:
        return "lateral"
    if angle <= down:
        return "down"
    if angle >= up:
        return "up"
    return "lateral"


def classify(velocity: Sequence[float], event: str, table: MotionFeatures) -> str | None:
    """The Table IV value of ``velocity`` in the speed range that ``event`` selects."""
    low, high = table.ranges[event]
    vx, vy, vz = (float(c) for c in velocity)
    speed = speed_class(math.sqrt(vx * vx + vy * vy + vz * vz), low, high)
    direction = direction_class(velocity, table.angle_down, table.angle_up)
    for row in table.rows:
        if row.speed == speed and row.direction in (None, direction):
            return row.value
    return None
