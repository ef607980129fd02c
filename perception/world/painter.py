"""The painter's algorithm of the renderer: gray levels, prepared boxes, occlusion order.

World side of perception (used by ``perception.world.render``). Boxes are drawn
far to near; the order comes from separating planes, exact for disjoint
axis-aligned boxes (``occludes``, ``paint_order``).
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np

# Gray levels (documented in docs/vision.md; detectors key their thresholds on them).
BACKGROUND = 0
HAND_GRAY = 128
ARM_GRAY = 80
CREASE_GRAY = 60
FLAT = {"hand": HAND_GRAY, "arm": ARM_GRAY}

SHIFT = 4  # sub-pixel bits for cv2 polygon vertices
EPS_MM = 0.5  # boxes closer than this along an axis count as touching (stacked)


class Drawn:
    """A box prepared for drawing: world bounds, and per camera its faces and image bounds."""

    __slots__ = ("kind", "lo", "hi", "faces", "creases", "bbox", "dist", "seen")

    def __init__(self, kind, lo, hi, faces, creases, bbox, dist) -> None:
        """Store the prepared drawing data (see ``Renderer._prepare``)."""
        self.kind, self.lo, self.hi = kind, lo, hi
        self.faces, self.creases, self.bbox, self.dist = faces, creases, bbox, dist
        self.seen = -10  # the last composed frame that contained this box

    def draw(self, img: np.ndarray, cam: str) -> None:
        """Fill the visible faces in ``cam``'s image, then the crease lines of a block."""
        for quad, color in self.faces[cam]:
            cv2.fillConvexPoly(img, quad, color, cv2.LINE_8, SHIFT)
        if self.creases is not None:
            cv2.polylines(img, self.creases[cam], True, CREASE_GRAY, 1, cv2.LINE_8, SHIFT)


def occludes(a: Drawn, b: Drawn, cam: str, eye: Sequence[float]) -> int:
    """+1 if ``a`` may hide part of ``b`` in ``cam``, -1 for the reverse, 0 if unrelated.

    Two disjoint axis-aligned boxes have a separating plane normal to some axis; the
    box on the eye's side of that plane is the nearer one wherever their images overlap.
    """
    p, q = a.bbox[cam], b.bbox[cam]
    if p[0] >= q[2] or q[0] >= p[2] or p[1] >= q[3] or q[1] >= p[3]:
        return 0
    for k in range(3):
        if a.hi[k] <= b.lo[k] + EPS_MM:
            return 1 if eye[k] < (a.hi[k] + b.lo[k]) / 2.0 else -1
        if b.hi[k] <= a.lo[k] + EPS_MM:
            return 1 if eye[k] > (b.hi[k] + a.lo[k]) / 2.0 else -1
    # Interpenetrating (e.g. fingers pressed into a block): the nearer one wins.
    return 1 if a.dist[cam] < b.dist[cam] else -1


def paint_order(items: Sequence[Drawn], cam: str, eye: Sequence[float]) -> list[int]:
    """Far-to-near drawing order (indices into ``items``) for the painter's algorithm."""
    n = len(items)
    kinds = {it.kind for it in items}
    if n < 2 or (len(kinds) == 1 and kinds <= FLAT.keys()):
        # One flat gray without crease lines (a hand's palm and fingers): any order paints
        # the same pixels.
        return list(range(n))
    neg = [-it.dist[cam] for it in items]
    order = sorted(range(n), key=neg.__getitem__)
    out: list[int] = []
    while order:  # stable topological sort: draw first a box that hides nothing remaining
        for j, a in enumerate(order):
            it = items[a]
            if all(occludes(it, items[b], cam, eye) <= 0 for b in order if b != a):
                out.append(order.pop(j))
                break
        else:  # a cycle of overlapping boxes: keep the distance order
            out.append(order.pop(0))
    return out
