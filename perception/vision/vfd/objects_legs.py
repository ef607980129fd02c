"""Blocks standing side by side under a wider one (Sec. IX-B3, issue #12 class 5).

A plate resting on two posts hides the posts' tops from the top camera: its top
face is the only one there, and the column under it, down to the table, fits no
shape. The side camera shows what it is: below the plate, the posts' front
faces with the table between them. Each run of front-face pixels across the
column, halfway down the part under the cover, is a block standing there: its
width is the run's, its height the rest of the column, and where its front face
meets the support (the run's bottom edge in the image) gives how far back it
stands. The shape database names each one; the upper block is the one whose
footprint is the top face and whose height leaves that rest.

One upright block under an overhang (a slab on a narrower cube) is a stack of
two, read by ObjectFinder._hidden_stack from the seam's crease; this module
reads the rest: several blocks under one, or one that leaves table showing on
both sides of the column's centre.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from perception.vision.vfd.base import DARK_MAX
from perception.vision.vfd.objects_rings import FRONT_BAND

FACE_MM = 8.0  # the top face is the upper block's own within this (summed on x and y)
FIT_MM = 12.0  # each block under it must be this near a shape (width and height)
GAP_PX = 2  # table showing between two blocks: at least this many dark pixels
MIN_REST_MM = 5.0

Reading = tuple[str, tuple[float, float, float], tuple[float, float, float], float]


def legs_under(cam, side: np.ndarray, obj, base: float, front: float,
               shapes: Mapping[str, Sequence[float]], smallest_mm: float
               ) -> list[Reading] | None:
    """``obj`` (a column read from its top face down to ``base``) as an upper block
    on blocks side by side, each a (name, centre, size, mismatch) reading; or None.
    ``front``: the column's front edge (y, mm)."""
    sx, sy, sz = obj.size
    cx, cy = obj.position[:2]
    best = None
    for top_name, (tx, ty, tz) in shapes.items():
        if abs(tx - sx) + abs(ty - sy) > FACE_MM or sz - tz < MIN_REST_MM:
            continue
        rest = sz - tz
        runs = _runs(cam, side, (cx - sx / 2.0, cx + sx / 2.0), front, base + rest / 2.0)
        if runs is None:
            continue
        legs, err = [], abs(tx - sx) + abs(ty - sy)
        for u0, u1, v in runs:
            seen_at = _front_of(cam, side, (u0 + u1) // 2, v, base)
            if seen_at is not None and seen_at > front + sy:
                continue  # a block behind the cover, seen under it
            y0 = max(seen_at if seen_at is not None else front, front)
            # the edges run through the creases that bound the run, on the face's plane
            x0 = cam.point_on_plane((u0 - 1.0, float(v)), 1, y0)[0]
            x1 = cam.point_on_plane((u1 + 1.0, float(v)), 1, y0)[0]
            width = float(x1 - x0)
            if width < 0.6 * smallest_mm:
                continue  # a sliver: an edge of the block behind, not one standing here
            fits = {n: abs(lx - width) + abs(lz - rest) for n, (lx, ly, lz) in shapes.items()
                    if ly <= sy + FACE_MM}
            if not fits or min(fits.values()) > FIT_MM:
                return None
            name = min(fits, key=fits.get)
            ly = float(shapes[name][1])
            y0 = min(y0, front + max(0.0, sy - ly))  # under the cover, which hides its top
            legs.append((name, (float(x0 + x1) / 2.0, float(y0 + ly / 2.0), base + rest / 2.0),
                         (width, ly, rest), fits[name]))
            err += fits[name]
        if legs and (best is None or err < best[0]):
            top = (top_name, (cx, cy, base + rest + tz / 2.0), (sx, sy, sz - rest), err)
            best = (err, [*legs, top])
    if best is None or best[0] >= obj.mismatch:
        return None
    return best[1]


def _runs(cam, side: np.ndarray, xs: tuple[float, float], front: float, z: float
          ) -> list[tuple[int, int, int]] | None:
    """Runs (u0, u1, row) of front-face pixels across the column at height ``z``, or
    None unless the table shows between them or beside one (the column is not solid)."""
    uv = cam.project(np.array([[xs[0], front, z], [xs[1], front, z]]))
    v = int(np.rint(uv[:, 1].mean()))
    ua, ub = int(np.ceil(uv[0, 0])), int(np.floor(uv[1, 0]))
    if not (0 <= v < side.shape[0] and 0 <= ua < ub < side.shape[1]):
        return None
    row = side[v, ua:ub + 1]
    face = (row >= FRONT_BAND[0]) & (row <= FRONT_BAND[1])
    dark = row[1:-1] <= DARK_MAX  # the end pixels may be the column's own outline
    if dark.sum() < GAP_PX or not face.any():
        return None
    runs, start = [], None
    for i, f in enumerate([*face.tolist(), False]):
        if f and start is None:
            start = i
        elif not f and start is not None:
            runs.append((ua + start, ua + i - 1, v))
            start = None
    if len(runs) == 1 and not (dark[:max(0, runs[0][0] - ua - 1)].any() and
                               dark[runs[0][1] - ua:].any()):
        return None  # one block under a cover overhanging one side: a stack (_hidden_stack)
    return runs


def _front_of(cam, side: np.ndarray, u: int, v: int, base: float) -> float | None:
    """How far back (y, mm) the front face through pixel (u, v) stands: its lowest row,
    where it meets the plane at ``base`` (the crease row below it)."""
    col = side[v:, u]
    face = (col >= FRONT_BAND[0]) & (col <= FRONT_BAND[1])
    off = int(np.argmin(face)) if not face.all() else len(face)
    if off == 0:
        return None
    return float(cam.point_on_plane((float(u), float(v + off)), 2, base)[1])
