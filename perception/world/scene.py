"""The scene: what the renderer sees of the world each frame (plain data, no pymunk)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Box:
    """One axis-aligned (up to an x-z tilt) box of the workspace, in world millimetres."""

    kind: str  # "block" | "hand" (palm or finger) | "arm"
    center: tuple[float, float, float]  # mm, world frame (z up from the table top)
    size: tuple[float, float, float]  # mm, full extents along x, y, z (axis-aligned)
    angle: float = 0.0  # rotation about the world y axis (radians), x-z plane tilt
    name: str = ""  # for debugging and ground truth only; renderers ignore it
