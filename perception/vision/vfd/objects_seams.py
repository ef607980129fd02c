"""Rings of a stack read at their own seams (issue #12 class 5; the object-finder's stacks).

When the rings of a stack show from above as faces of their own, each framing the
one above it, neither ring's top face can be seen from the side camera, and each
takes the height of the face it frames, or of the whole column: lifted that high,
its footprint comes out too small. Its own height is a seam in the side view: a
crease on the front face, where the face below is as wide as the ring's footprint
at that height. ObjectFinder.find seats the rings before it reads the columns.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from perception.vision.vfd.objects_match import frames
from perception.vision.vfd.objects_rings import (
    Box,
    area_of,
    crease_at,
    holds_centre,
    thin,
    width_at,
)

SEAT_MM = 4.5  # a frame's footprint and the front face under its seam agree this well
SEAT_TIE_MM = 2.0  # seams whose faces fit within this of the best fit about as well


def seat_rims(boxes: list[Box], cam, side: np.ndarray,
              footprint: Callable[[tuple, float], tuple[float, float, float, float]],
              thinnest: float, sliver_px: float, measured: set[int] = frozenset()
              ) -> list[Box]:
    """``boxes`` with each face that frames a higher one or holds its centre (a whole
    ring, or what the upper block leaves of it: an L or a U), yet was measured too high
    for a block to stand between, lowered to its own seam where the side view shows one.

    Rings of a stack (a tile on a cube on a block: two 5 mm rings) have top faces too
    thin to see from the side; each ring then took the height of the top face it frames
    or of the whole column, and its footprint, lifted that high, came out too small
    (rearrange 1036, 1042: the block's ring read as a 40 mm cube). Its own height is a
    seam: a crease on the front face where the face below is as wide as the ring's
    footprint at that height (``seam_height``). Frames are seated inmost first, so an
    outer ring is judged against the rings inside it at their own heights. A face
    thinner than ``sliver_px`` is a piece of a rim, never the face a rim is under.

    The boxes in ``measured`` took their height from a side-view top face of their own:
    they stay. Near the table's edges a tall stack's top face, shifted outwards by the
    top camera's perspective, holds the centre of what the stack leaves visible of the
    face under it (a cube on three cubes on a slab at (250, 350), helper e08).
    """
    out = list(boxes)
    for k in sorted(range(len(boxes)), key=lambda i: area_of(boxes[i][2])):
        h, _, rect = out[k]
        if k in measured:
            continue
        inner = [(g, f) for j, (g, f, q) in enumerate(out) if j != k and not thin(
            q, sliver_px) and (frames(rect, q) or holds_centre(rect, q) and beyond(rect, q))]
        if not inner:
            continue
        highest = max(g for g, _ in inner)
        if h < highest - max(3.0, thinnest - 3.0):
            continue  # a lower block's own top face, with room for the one on it
        # the lower block's front is at least as far forward as the upper block's (the
        # upper block may hide the front of the ring from above)
        seat = seam_height(cam, side, footprint, rect, highest - 3.0,
                           min(f[1] for _, f in inner))
        if seat is not None:
            out[k] = (seat, footprint(rect, seat), rect)
    return out


def beyond(rect: Sequence[float], inner: Sequence[float], tol: float = 1.0) -> bool:
    """Whether pixel rectangle ``rect`` reaches past ``inner`` on some side (more than
    ``tol`` px): what a rim around it does, and the top face of a block standing on
    the block whose face ``inner`` is does not (bench 1103 at 2x, a cube on a disc)."""
    return rect[0] < inner[0] - tol or rect[1] < inner[1] - tol or \
        rect[2] > inner[2] + tol or rect[3] > inner[3] + tol


def seam_height(cam, side: np.ndarray,
                footprint: Callable[[tuple, float], tuple[float, float, float, float]],
                rect: Sequence[float], below: float, front: float = np.inf) -> float | None:
    """The height under ``below`` (mm) where the side view shows a seam on the front face
    of the block whose top face is pixel rectangle ``rect``, that face as wide as the
    rectangle's footprint there (within SEAT_MM), or None. The front face is at the
    footprint's front edge, or at ``front`` (y, mm) where that lies further forward.

    The heights whose projection falls on the crease line itself form runs, a run per
    crease; the run whose face width fits best (the highest of those that fit about as
    well) is the seam, and its middle the height (the width varies too little with the
    height to place the seam within a run)."""
    runs: list[list[tuple[float, float]]] = []  # (height, width error), per crease
    last = None
    for h in np.arange(5.0, below, 0.5):
        x0, y0, x1, y1 = footprint(rect, float(h))
        cx, y0 = (x0 + x1) / 2.0, min(y0, front)
        run = width_at(cam, side, (cx, y0, h - SEAT_MM)) if crease_at(
            cam, side, (cx, y0, h), reach=0) else None
        err = abs(run[0] - (x1 - x0)) if run is not None else np.inf
        if err <= SEAT_MM:
            if last is None or h - last > 0.75:
                runs.append([])
            runs[-1].append((float(h), float(err)))
            last = h
    if not runs:
        return None
    # of seams whose faces fit about as well, the highest: a ring is the top of the block
    # right under the one it frames (two equal discs under a cube: the one between the
    # discs was taken, and the cube read 48 mm tall; round 14, 84)
    least = min(e for r in runs for _, e in r)
    best = max((r for r in runs if min(e for _, e in r) <= least + SEAT_TIE_MM),
               key=lambda r: r[0][0])
    return float(np.mean([h for h, _ in best]))
