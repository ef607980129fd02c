"""Boxes drawn as silhouettes into both views and compared with the images.

The monitor's look (objects_posed.py) asks whether the views agree with blocks
standing at given poses: each box (centre, size) is projected through the camera
models and filled; the views' non-dark pixels are what is solid.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.vision.vfd.base import DARK_MAX
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources

_PIXEL = np.ones((3, 3), np.uint8)  # one pixel around each pixel
_SPECK = np.ones((2, 2), np.uint8)  # wrong areas thinner than this are noise, not a block
# A block whose own silhouette, off its outline band and off every other block's, covers
# at least OWN_PX pixels in a view can be seen there; it is not there when more than
# UNSHOWN_SHARE of those pixels are dark (``unshown``).
OWN_PX = 8
UNSHOWN_SHARE = 0.5
Box = tuple[Sequence[float], Sequence[float]]  # centre, size


class Silhouettes:
    """Wrong pixels of a set of boxes (centre, size) against both views' non-dark masks."""

    def __init__(self, cameras: Mapping[str, Camera], images: Mapping[str, np.ndarray],
                 sizes: Sequence[Sequence[float]] = ()) -> None:
        """``images`` holds the ``top`` and ``side`` gray views; ``sizes``, the blocks
        expected, sets the smallest top face looked for in the top view (``faces``)."""
        self.cameras = cameras
        self.finder = ObjectFinder(cameras, VisionResources())
        self.faces = self.finder.top_faces(images["top"], self.finder.smallest_face_px(
            dict(enumerate(sizes)))) if sizes else []  # top faces' pixel rectangles
        self.solid = {n: (images[n] > DARK_MAX).astype(np.uint8) for n in ("top", "side")}

    def wrong(self, boxes: Sequence[tuple[Sequence[float], Sequence[float]]],
              within: Sequence[tuple[Sequence[float], Sequence[float]]] | None = None,
              edges: bool = True) -> int:
        """Pixels where the boxes' silhouettes and the views disagree, both views summed;
        only near the silhouettes of the boxes ``within`` when given; without ``edges``,
        not on the one-pixel band either side of the drawn outlines (a pose off by less
        than a pixel flips a whole row of a long edge there: a beam 0.5 mm off in x and y
        flips half its outline in the top view), and not in strips one pixel thin."""
        total = 0
        for name, actual in self.solid.items():
            drawn = self._draw(name, boxes, actual.shape)
            diff = cv2.bitwise_xor(drawn, actual)
            if not edges:
                diff[cv2.dilate(drawn, _PIXEL) > cv2.erode(drawn, _PIXEL)] = 0
            if within is not None:
                near = cv2.dilate(self._draw(name, within, actual.shape), np.ones((7, 7), np.uint8))
                diff = cv2.bitwise_and(diff, near)
            if not edges:  # lone pixels are speckle (pixel noise), not a block
                diff = cv2.morphologyEx(diff, cv2.MORPH_OPEN, _SPECK)
            total += int(cv2.countNonZero(diff))
        return total

    def moves(self, boxes: Sequence[Box], moving: int, shifts: Sequence[Sequence[float]]
              ) -> list[dict[str, int]]:
        """Wrong pixels per view with box ``moving`` shifted by each (dx, dy), not counting
        strips one pixel thin: a long edge of any block a fraction of a pixel off flips a
        whole row, which a block slid along it fills (a cube on a slab 0.7 mm off slid
        6 mm toward its front edge to cover the slab's row). The other boxes are drawn
        once, and only the pixels the moving box may cover or uncover are compared."""
        center, size = boxes[moving]
        posed = [(tuple(np.add(center, (d[0], d[1], 0.0))), size) for d in shifts]
        rest = [b for k, b in enumerate(boxes) if k != moving]
        out: list[dict[str, int]] = [{} for _ in shifts]
        for name, actual in self.solid.items():
            h, w = actual.shape
            u0, v0, u1, v1 = _rect(self.cameras[name], posed + [boxes[moving]], h, w)
            others = self._draw(name, rest, actual.shape)[v0:v1, u0:u1]
            seen = actual[v0:v1, u0:u1]
            for k, box in enumerate(posed):
                drawn = self._draw(name, [box], actual.shape)[v0:v1, u0:u1] | others
                diff = cv2.morphologyEx((drawn != seen).astype(np.uint8), cv2.MORPH_OPEN, _SPECK)
                out[k][name] = int(cv2.countNonZero(diff))
        return out

    def outline(self, boxes: Sequence[tuple[Sequence[float], Sequence[float]]]) -> int:
        """Pixels on the outlines of the boxes' silhouettes, both views summed."""
        total = 0
        for name, actual in self.solid.items():
            drawn = self._draw(name, boxes, actual.shape)
            total += int(cv2.countNonZero(drawn - cv2.erode(drawn, _PIXEL)))
        return total

    def _draw(self, name: str, boxes: Sequence[tuple[Sequence[float], Sequence[float]]],
              shape: tuple[int, ...]) -> np.ndarray:
        """The boxes' silhouettes in camera ``name``."""
        drawn = np.zeros(shape, np.uint8)
        for center, size in boxes:
            corners = np.array([[center[k] + s * size[k] / 2.0 for k, s in enumerate((a, b, c))]
                                for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)])
            uv = self.cameras[name].project(corners)
            hull = cv2.convexHull(np.rint(uv * 16).astype(np.int32))
            cv2.fillConvexPoly(drawn, hull, 1, cv2.LINE_8, 4)
        return drawn

    def unshown(self, box: Box, others: Sequence[Box]) -> bool:
        """Whether a view shows mostly dark where only ``box`` would be seen: of its silhouette
        off its one-pixel outline band and off the silhouettes of ``others`` (grown by a
        pixel), at least OWN_PX pixels, more than UNSHOWN_SHARE of them dark. A block
        hidden behind or under others has no such pixels and is not judged; a 15 mm cube
        on a 20 mm one shows 12 side-view pixels above it, all dark once it was taken
        away, while the structure's silhouettes as a whole were within their tolerance
        (helper round 15, AH)."""
        for name, actual in self.solid.items():
            own = cv2.erode(self._draw(name, [box], actual.shape), _PIXEL)
            if others:
                own[cv2.dilate(self._draw(name, others, actual.shape), _PIXEL) > 0] = 0
            area = int(cv2.countNonZero(own))
            if area >= OWN_PX and \
                    cv2.countNonZero(cv2.bitwise_and(own, 1 - actual)) > UNSHOWN_SHARE * area:
                return True
        return False


def _rect(cam: Camera, boxes: Sequence[Box], h: int, w: int) -> tuple[int, int, int, int]:
    """The pixel window (u0, v0, u1, v1) holding the boxes' images, a pixel around."""
    corners = np.array([[c[k] + s * z[k] / 2.0 for k, s in enumerate((a, b, e))]
                        for c, z in boxes for a in (-1, 1) for b in (-1, 1) for e in (-1, 1)])
    uv = cam.project(corners)
    lo, hi = np.floor(uv.min(axis=0)) - 2, np.ceil(uv.max(axis=0)) + 3
    return (int(np.clip(lo[0], 0, w)), int(np.clip(lo[1], 0, h)),
            int(np.clip(hi[0], 0, w)), int(np.clip(hi[1], 0, h)))
