"""Top faces the side camera cannot see: a block behind a taller one (the object-finder).

The side camera looks along +y, raised about 20 degrees. A block standing behind
a taller one is hidden from it, top face and all, and the side view says nothing
of its height: lifted to any height at which it stays hidden, its top face
projects onto the nearer block's image. The height search then pairs it with
the nearer block's own top face (generated stacked-start 1176: a 50 mm brick
behind a 100 mm stack of two, read 75 mm tall and split into two bricks), or the
column search stops at the nearer block's top edge (1030: a 40 mm cube behind an
80 mm stack, read 61 mm tall). Such a face takes the height of the shape its
footprint names, if that height hides it too: the one reading of many that needs
no block nobody can see.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import cv2
import numpy as np

from perception.vision.vfd.objects_rings import holds_centre

HIDDEN_SHARE = 0.6  # of a top face's side-view image inside nearer blocks' images: unseen
APART_MM = 10.0  # a nearer block stands this far in front: not a ring of the same stack
SAME_XY_MM = 8.0  # a footprint this close to a shape's (summed over x and y) may be it

Box = tuple[float, tuple[float, float, float, float], tuple]  # (height, footprint, rect)
Footprint = Callable[[tuple, float], tuple[float, float, float, float]]


def unseen_heights(boxes: list[Box], cam, size: tuple[int, int], footprint: Footprint,
                   shapes: Mapping[str, Sequence[float]]) -> list[Box]:
    """``boxes`` with each top face that the blocks nearer the side camera hide at its
    height lowered to the height of the shape its footprint names, where that hides it
    too. ``size``: the side image's (width, height)."""
    out = list(boxes)
    for k, (h, (x0, y0, x1, y1), rect) in enumerate(boxes):
        nearer = [b for j, b in enumerate(boxes) if j != k and b[1][3] < y0 - APART_MM]
        if not nearer or any(j != k and (holds_centre(r, rect) or holds_centre(rect, r))
                             for j, (_, _, r) in enumerate(boxes)):
            continue  # nothing in front; or a face of a stack, whose column the seams read
        front = np.zeros((size[1], size[0]), np.uint8)
        for g, (a0, b0, a1, b1), _ in nearer:
            _fill(front, cam, [(x, y, z) for x in (a0, a1) for y in (b0, b1) for z in (0.0, g)])
        if _hidden(front, cam, footprint(rect, h), h) < HIDDEN_SHARE:
            continue
        tall = [float(s[2]) for s in shapes.values() if float(s[2]) < h - 3.0 and
                abs(float(s[0]) - (x1 - x0)) + abs(float(s[1]) - (y1 - y0)) <= SAME_XY_MM]
        for z in sorted(tall, reverse=True):
            if _hidden(front, cam, footprint(rect, z), z) >= HIDDEN_SHARE:
                out[k] = (z, footprint(rect, z), rect)
                break
    return out


def _hidden(front: np.ndarray, cam, fp: tuple[float, float, float, float], h: float) -> float:
    """Share of the side-view image of the top face ``fp`` at height ``h`` inside ``front``."""
    face = np.zeros_like(front)
    x0, y0, x1, y1 = fp
    _fill(face, cam, [(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)])
    n = int(face.sum())
    return float((face & front).sum()) / n if n else 0.0


def _fill(mask: np.ndarray, cam, points: list) -> None:
    """Draw the convex hull of the world ``points``' projections into ``mask`` (1s)."""
    uv = np.rint(cam.project(np.array(points, float)) * 16).astype(np.int32)
    cv2.fillConvexPoly(mask, cv2.convexHull(uv), 1, cv2.LINE_8, 4)
