"""Synthetic scenes for the vision tests: blocks and a gripper-shaped hand, rendered."""

from __future__ import annotations

import numpy as np

from perception.vision.camera import default_cameras
from perception.vision.frames import Frame
from perception.world.render import Renderer
from perception.world.scene import Box

CAMS = default_cameras()


def hand(x: float, y: float, z: float, opening: float = 60.0, axis: int = 0) -> list[Box]:
    """Palm and two fingers around the grip centre (x, y, z), fingertips 10 mm below it;
    the jaws close along x (``axis`` 0) or y (1: the wrist turned)."""
    off = (opening + 10.0) / 2.0
    fingers = ((x - off, y), (x + off, y)) if axis == 0 else ((x, y - off), (x, y + off))
    size = (10.0, 20.0, 50.0) if axis == 0 else (20.0, 10.0, 50.0)
    return [Box("hand", (x, y, z + 55.0), (50.0, 50.0, 30.0), name="palm"),
            *(Box("hand", (fx, fy, z + 15.0), size, name=f"finger-{side}")
              for (fx, fy), side in zip(fingers, ("left", "right"), strict=True))]


def block(x: float, y: float, size=(30.0, 30.0, 50.0), z0: float = 0.0) -> Box:
    """A block of ``size`` resting at height ``z0`` with its centre over (x, y)."""
    return Box("block", (x, y, z0 + size[2] / 2.0), tuple(map(float, size)))


class Film:
    """Renders scenes into numbered, timed frames at 30 fps."""

    def __init__(self, noise: float = 2.0, seed: int = 0) -> None:
        """A renderer with the default cameras."""
        self.renderer = Renderer(CAMS, pixel_noise=noise, seed=seed)
        self.index = 0

    def shoot(self, scene: list[Box]) -> Frame:
        """The next frame of ``scene``."""
        imgs = self.renderer.render(scene)
        f = Frame(self.index, self.index / 30.0, imgs["top"], imgs["side"])
        self.index += 1
        return f


def dist(a, b) -> float:
    """Euclidean distance."""
    return float(np.linalg.norm(np.asarray(a, float) - np.asarray(b, float)))
