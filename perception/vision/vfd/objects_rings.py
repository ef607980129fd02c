"""The lower block of a stack whose top face shows only in part (Sec. IX-B3, issue #12 class 5).

From the top camera, a block standing on a wider one hides part of the lower
block's top: its upper faces lean outwards in the image and cover the rim on
the side away from the camera's nadir. What is left of the rim is an L or a U,
one top-face region whose rectangle holds the upper face's centre. Measured as
it is, that rectangle is the visible rim, not the block: a 30 mm post on a
40 mm cube near the workspace's edge was read as a second post.

The rim still gives the lower block's height and every edge it shows. An edge
is shown on the sides where the rim reaches beyond what the upper block covers
(its footprint, and its top face seen down to the rim's height); on the other
sides the database shape decides, within the room the cover leaves.

Stacks whose rings are too thin to show at all (three blocks, 5 mm rings) are
read from the side view: a crease at the seam (``crease_at``) and the front
face's width below it (``width_at``), ObjectFinder._hidden_stack. ``consistent``
drops what such stacks leave behind: ring slivers read as columns, and one
stack read twice.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from itertools import combinations
from typing import Any

import numpy as np

from lbw_engine.model.geometry import footprints_meet
from perception.vision.vfd.base import DARK_MAX
from perception.vision.vfd.objects_match import frames, nearest

RING_HIDDEN_MM = 6.0  # a top-face ring this thin (2 px from above) merges into its outline
CREASE_MAX = 110  # crease lines are drawn at 60, faces at 170 and brighter
FRONT_BAND = (150, 190)  # faces facing -y (the side camera) are drawn at 170
FACE_SHARE = 0.8  # a front face's run between creases has this share in FRONT_BAND at least

Box = tuple[float, tuple[float, float, float, float], tuple]  # (height, footprint, pixel rect)

STACK_XY_MM = 8.0  # a top face this close to a shape's footprint may be that shape's
EDGE_MM = 1.5  # a rim edge counts as seen when it lies this far outside the cover
# an outline this much wider than the block on it, rings on both sides, shows no ring
UNSEEN_RINGS_MM = 2.0 * (RING_HIDDEN_MM + EDGE_MM)


def find_rims(boxes: list[Box], sliver_px: float, thinnest: float = 0.0,
              shapes: Mapping[str, Sequence[float]] | None = None) -> dict[int, tuple]:
    """Upper face -> the pixel rectangle of the rim seen around it, measured as high as it.

    A narrow rim is hardly seen from the side and may come out as high as the column
    it belongs under; its block is then measured with that column (the seam in the
    side view gives its height, ObjectFinder._hidden_stack). Such a rim frames the
    upper face (a whole ring), or holds its centre (an L or a U: the rest is hidden),
    or breaks into slivers thinner than any top face the database allows
    (``sliver_px``) along the upper face's outline. A framing face is a rim when it is
    measured less than the thinnest shape (``thinnest``, mm) below the upper face, less
    3 mm: no block of the database could stand between (a tile on a cube on a block,
    bench seed 2033: the merged rings came out at 106 mm under the tile's 110 mm).
    An L or a U is a rim of the block under the upper face only if no block of the
    database (``shapes``) fits between them: else it is the top face of a lower block,
    with blocks hidden between (``room_between``).
    """
    parts: dict[int, list[tuple]] = {}
    # A face framing a lower one is measured too high: a box there would hide the lower
    # face. It is a rim (of the stack under that face), never the upper face of one.
    over = {j for j, (h, _, r) in enumerate(boxes)
            if any(k != j and frames(r, q) and h > g + 3.0 for k, (g, _, q) in enumerate(boxes))}
    for i, (h_out, _, outer) in enumerate(boxes):
        for j, (h_in, _, inner) in enumerate(boxes):
            if i == j or thin(inner, sliver_px) or j in over:
                continue  # a face thinner than any top face is a rim piece, never framed
            sliver = thin(outer, sliver_px) and _touches(outer, inner)
            framed = frames(outer, inner) and h_out >= h_in - max(3.0, thinnest - 3.0)
            partial = not frames(outer, inner) and area_of(outer) > area_of(inner) and \
                holds_centre(outer, inner) and h_out < h_in + 3.0 and \
                not room_between(boxes[j], h_out, thinnest, shapes)
            if sliver or framed or partial:
                parts.setdefault(j, []).append(outer)
    return {j: _union(*p) if len(p) > 1 else p[0] for j, p in parts.items()}


def room_between(upper: Box, low: float, thinnest: float,
                  shapes: Mapping[str, Sequence[float]] | None) -> bool:
    """Whether a block of the database fits between height ``low`` and the bottom of
    ``upper`` read as the tallest shape its footprint may be: three cubes on a slab near
    the table's corner show the slab's top as an L around the top cube (helper e08)."""
    h, footprint, _ = upper
    tall = heights_of(footprint, shapes or {})
    return bool(tall) and h - max(tall) - low > max(3.0, thinnest - 3.0)


def heights_of(footprint: Sequence[float], shapes: Mapping[str, Sequence[float]]
               ) -> list[float]:
    """Heights of the shapes a block with this top-face ``footprint`` (x0, y0, x1, y1; mm)
    may be: their x and y sizes within STACK_XY_MM of its extents, summed."""
    x0, y0, x1, y1 = footprint
    return [float(s[2]) for s in shapes.values()
            if abs(float(s[0]) - (x1 - x0)) + abs(float(s[1]) - (y1 - y0)) <= STACK_XY_MM]


def split_rims(boxes: list[Box], skip: set[int], sliver_px: float, ringed: set[int] = frozenset()
               ) -> dict[int, tuple[tuple, tuple[int, ...]]]:
    """Upper face -> (pixel rectangle, pieces) of a rim its block cuts in two.

    A block standing across a longer one (a post on the middle of a beam) hides the
    middle of the lower top face: what shows is two faces at one height, one on each
    side of the upper face and touching it, neither holding its centre (bench seed
    1139: a brick on a 130 mm beam read as two bricks and a 70 mm column). Two such
    faces are pieces of one rim when their extents across the cut overlap by half the
    shorter one; the rectangle holding both is the rim's. Their heights must agree
    when they lie side by side along x; along y the upper block hides the far half's
    top from the side camera, and its height is whatever the search found. Whether
    a lower block is really there is the side view's to say (a crease at the seam,
    ObjectFinder._hidden_stack): two blocks standing on either side of a taller one
    look the same from above.

    ``skip``: faces never cut across (rims), though they may be pieces; ``ringed``:
    faces with a rim of their own, never pieces. A face with a rim may still stand
    across a longer block, its rim a sliver at one end that is then one piece (a
    cube 30 mm off a 110 mm plank's centre left a 12.5 mm sliver at its end, read as
    a 14 mm cube of its own).
    """
    out: dict[int, tuple[tuple, tuple[int, ...]]] = {}
    for j, (h_up, _, up) in enumerate(boxes):
        if j in skip or thin(up, sliver_px):
            continue
        cx, cy = (up[0] + up[2]) / 2.0, (up[1] + up[3]) / 2.0
        near = [i for i, (h, _, r) in enumerate(boxes) if i != j and i not in ringed
                and h < h_up - 3.0 and _touches(r, up) and not holds_centre(r, up)]
        best = None
        for a, b in combinations(near, 2):
            (ha, _, ra), (hb, _, rb) = boxes[a], boxes[b]
            for axis, centre in ((0, cx), (1, cy)):
                if axis == 0 and abs(ha - hb) > 3.0:
                    continue  # a cut along y: the half behind is hidden from the side
                lo, hi = (ra, rb) if ra[axis] < rb[axis] else (rb, ra)
                across = 1 - axis
                overlap = min(lo[across + 2], hi[across + 2]) - max(lo[across], hi[across])
                short = min(lo[across + 2] - lo[across], hi[across + 2] - hi[across])
                if lo[axis + 2] <= centre <= hi[axis] and overlap >= 0.5 * short:
                    rect = _union(ra, rb)
                    if best is None or area_of(rect) > area_of(best[0]):
                        best = (rect, (a, b))
        if best is not None:
            out[j] = best
    return out


def complete_rims(boxes: list[Box], skip: set[int],
                  footprint: Callable[[tuple, float], tuple[float, float, float, float]],
                  shapes: Mapping[str, Sequence[float]]) -> list[Box]:
    """``boxes`` with every partly hidden rim's footprint replaced by its block's.

    A rim is a top face whose pixel rectangle holds the centre of a higher face's
    without framing it (a whole ring frames it and is measured as it is)."""
    out = list(boxes)
    for k, (h, rim, rect) in enumerate(boxes):
        uppers = [b for j, b in enumerate(boxes) if j != k and j not in skip and b[0] > h + 3.0
                  and holds_centre(rect, b[2]) and not frames(rect, b[2])]
        if k in skip or not uppers:
            continue
        h_up, foot, up_rect = max(uppers, key=lambda b: b[0])
        cover = _union(foot, footprint(up_rect, h))  # its top face, seen down to the rim
        cx, cy = (foot[0] + foot[2]) / 2.0, (foot[1] + foot[3]) / 2.0
        base = max([b[0] for j, b in enumerate(boxes) if j != k and j not in skip
                    and b[0] < h - 3.0 and b[1][0] <= cx <= b[1][2] and b[1][1] <= cy <= b[1][3]],
                   default=0.0)
        done = complete_rim(rim, cover, (cx, cy), h - base, shapes)
        if done is not None:
            _, (x, y), (sx, sy), _ = done
            out[k] = (h, (x - sx / 2.0, y - sy / 2.0, x + sx / 2.0, y + sy / 2.0), rect)
    return out


def cover_of(obj, seen: Sequence[float]) -> tuple[float, float, float, float]:
    """What a found upper block hides at a lower height: its footprint and ``seen``, the
    extents of its top face seen down to that height."""
    (x, y), (sx, sy) = obj.position[:2], obj.size[:2]
    return _union((x - sx / 2.0, y - sy / 2.0, x + sx / 2.0, y + sy / 2.0), seen)


def _union(*rects: Sequence[float]) -> tuple[float, float, float, float]:
    """The extents (x0, y0, x1, y1) that hold all ``rects``."""
    return (min(r[0] for r in rects), min(r[1] for r in rects),
            max(r[2] for r in rects), max(r[3] for r in rects))


def _touches(a: Sequence[float], b: Sequence[float], gap: float = 2.0) -> bool:
    """Whether pixel rectangles ``a`` and ``b`` meet or lie within ``gap`` px."""
    return a[0] <= b[2] + gap and b[0] <= a[2] + gap and a[1] <= b[3] + gap and b[1] <= a[3] + gap


def table_between(top: np.ndarray, a: Sequence[float], b: Sequence[float]) -> bool:
    """Whether the top view shows table between two faces' pixel rectangles (their edges
    run through the creases): the pixels strictly between them, along their common
    stretch, mostly dark. Two faces at one height either side of a taller one are a rim
    it cuts in two only if they touch it; 20 mm blocks standing 6 mm in front of and
    behind a 30 mm cube are 2 px apart from it, and one of those is table."""
    for axis in (0, 1):
        lo, hi = (a, b) if a[axis] < b[axis] else (b, a)
        start, stop = int(np.floor(lo[axis + 2])) + 1, int(np.ceil(hi[axis])) - 1
        if stop < start:
            continue
        across = 1 - axis
        c0 = int(np.ceil(max(lo[across], hi[across]))) + 1
        c1 = int(np.floor(min(lo[across + 2], hi[across + 2]))) - 1
        if c1 < c0:
            continue
        strip = top[start:stop + 1, c0:c1 + 1] if axis == 1 else top[c0:c1 + 1, start:stop + 1]
        if strip.size and float(np.mean(strip <= DARK_MAX)) >= 0.5:
            return True
    return False


def area_of(rect: Sequence[float]) -> float:
    """Area of a rectangle (x0, y0, x1, y1)."""
    return (rect[2] - rect[0]) * (rect[3] - rect[1])


def holds_centre(outer, inner, tol: float = 1.0) -> bool:
    """Whether pixel rectangle ``outer`` holds the centre of rectangle ``inner``."""
    cx, cy = (inner[0] + inner[2]) / 2.0, (inner[1] + inner[3]) / 2.0
    return outer[0] - tol <= cx <= outer[2] + tol and outer[1] - tol <= cy <= outer[3] + tol


def complete_rim(rim: Sequence[float], cover: Sequence[float], upper: Sequence[float],
                 height: float,
                 shapes: Mapping[str, Sequence[float]], stacked: float | None = None
                 ) -> tuple[str, tuple[float, float], tuple[float, float], float] | None:
    """The lower block behind a partly hidden rim: (shape, centre x y, size x y, mismatch).

    ``rim``: the visible rim's world extents (x0, y0, x1, y1) at its height;
    ``cover``: the extents the upper block hides at that height; ``height``: the
    lower block's own height. Per axis, the block's extent is measured where both
    edges show; where one shows, the shape's size runs from it into the cover;
    the shape must be as long as the visible rim and no longer than the rim and
    the cover together. None when no shape fits within the room. When no shape's
    height is within ``stacked`` mm of ``height``, the part under the cover is a
    stack itself (three blocks whose rings merged): the rim is its top block's, and
    the shape is chosen by its outline alone (the caller splits the part again;
    bench 1105, a cube's ring over a block, completed as a 30 mm brick).
    """
    lo = np.array(rim[:2], float)
    hi = np.array(rim[2:], float)
    c_lo, c_hi = np.array(cover[:2], float), np.array(cover[2:], float)
    seen_lo, seen_hi = lo < c_lo - EDGE_MM, hi > c_hi + EDGE_MM
    room = np.maximum(hi, c_hi) - np.minimum(lo, c_lo)
    best = None
    tall = stacked is not None and all(abs(float(v[2]) - height) > stacked
                                       for v in shapes.values())
    for name, size in shapes.items():
        s = np.asarray(size, float)
        err = 0.0 if tall else abs(s[2] - height)
        for a in range(2):
            if seen_lo[a] and seen_hi[a]:
                err += abs(s[a] - (hi[a] - lo[a]))
            elif s[a] > room[a] + 2 * EDGE_MM + (seen_lo[a] or seen_hi[a]) * RING_HIDDEN_MM:
                # it would show beyond the cover; where the rim shows one edge, the other
                # side may hide a ring too thin to see (with no edge shown, the rim lies
                # inside the cover and says nothing of the block's outline)
                err = np.inf
            else:
                err += max(0.0, (hi[a] - lo[a]) - s[a])  # shorter than what is seen of it
        if np.isfinite(err) and (best is None or err < best[0]):
            best = (float(err), name, s)
    if best is None:
        return None
    err, name, s = best
    centre, extent = [], []
    for a in range(2):
        if seen_lo[a] and seen_hi[a]:
            centre.append((lo[a] + hi[a]) / 2.0)
            extent.append(hi[a] - lo[a])
        else:
            if seen_lo[a]:
                centre.append(lo[a] + s[a] / 2.0)
            elif seen_hi[a]:
                centre.append(hi[a] - s[a] / 2.0)
            else:
                centre.append(float(upper[a]))
            extent.append(float(s[a]))
    return name, (float(centre[0]), float(centre[1])), (float(extent[0]), float(extent[1])), err


def pieces(boxes: list[Box], rings: Mapping[int, tuple], sliver_px: float) -> set[int]:
    """The boxes that are a rim, or a sliver of one (a rim seen in several pieces): not
    the faces rimmed, nor a face that is both (the middle block of a three-block stack)."""
    return {i for i, b in enumerate(boxes) if b[2] in rings.values() or (
        i not in rings and thin(b[2], sliver_px) and any(within(b[2], r)
                                                          for r in rings.values()))}


def thin(rect: Sequence[float], px: float) -> bool:
    """Whether pixel rectangle ``rect`` is narrower than ``px`` on its shorter side."""
    return min(rect[2] - rect[0], rect[3] - rect[1]) < px


def within(rect: Sequence[float], outer: Sequence[float]) -> bool:
    """Whether pixel rectangle ``rect`` lies inside ``outer`` (a rim piece in its rim)."""
    return outer[0] <= rect[0] and outer[1] <= rect[1] and rect[2] <= outer[2] \
        and rect[3] <= outer[3]


def inside_thin_ring(top: Sequence[float], outline: Sequence[float]) -> bool:
    """Whether a block of footprint ``top`` can stand centred on a face the top view
    measured as ``outline`` with only a ring thinner than RING_HIDDEN_MM around it: the
    ring's creases leave no face pixel between them, so the measured outline is the
    lower block's (a cube on a block under a tile: three blocks, one face). Each
    measured edge may lie EDGE_MM out (bench 1106: a 50 mm block's outline under a
    cube, seen from the top camera's edge, measured 52.7 mm)."""
    return all(0.0 <= o - t <= UNSEEN_RINGS_MM
               for t, o in zip(top, outline, strict=False))


def thin_rings_only(cover: Sequence[float], lower: Sequence[float]) -> bool:
    """Whether a block of footprint ``lower`` can stand under one covering ``cover`` with
    what shows of its top, along each axis, no wider than a ring the top view cannot see
    (inside_thin_ring's bound); narrower along an axis hides it there."""
    return all(lo - c <= UNSEEN_RINGS_MM
               for c, lo in zip(cover, lower, strict=False))


def consistent(found: list, shapes: Mapping[str, Sequence[float]], fits_mm: float) -> list:
    """Drop readings that fit no shape and overlap the footprint of a lower block found
    under a stack: pieces of that block's thin ring (3 px here, 2 there, at pixel noise)
    read as columns of their own, their heights and so their footprints wrong. A piece
    of the lowest block's ring stands on the table as that block does, its column as
    high: it is no higher than the block (bench 1071 at 4x, a 6 x 33 x 46 mm "cube")."""
    def over(f: Any, g: Any) -> bool:  # footprints meet, or nearly
        return footprints_meet(f.position, f.size, g.position, g.size, tol=-RING_HIDDEN_MM)

    def top(f: Any) -> float:
        return f.position[2] + f.size[2] / 2.0

    def under(g: Any, f: Any) -> bool:  # g lower, or f a piece of g's own ring (as high)
        return g.position[2] < f.position[2] or abs(top(g) - top(f)) <= RING_HIDDEN_MM

    fit = [nearest(shapes, np.array(f.size))[1] for f in found]  # mm from the nearest shape
    kept = [i for i, f in enumerate(found) if fit[i] < fits_mm or not any(
        g is not f and fit[j] < fits_mm and under(g, f) and over(f, g)
        and any(h is not g and h is not f and h.position[2] > g.position[2] and over(h, g)
                for h in found)
        for j, g in enumerate(found))]
    # Two faces of one stack (a ring piece beside the top face, near the camera's axis)
    # can each be read as the whole stack: readings that fill the same space are one
    # block read twice; the one nearer a shape stays.
    out: list[int] = []
    for i in sorted(kept, key=lambda i: fit[i]):
        if not any(_shared(found[i], found[j]) > 0.5 for j in out):
            out.append(i)
    return [f for i, f in enumerate(found) if i in out]


def _shared(a: Any, b: Any) -> float:
    """The volume two readings' boxes share, as a share of the smaller box."""
    common = 1.0
    for k in range(3):
        lo = max(a.position[k] - a.size[k] / 2.0, b.position[k] - b.size[k] / 2.0)
        hi = min(a.position[k] + a.size[k] / 2.0, b.position[k] + b.size[k] / 2.0)
        common *= max(0.0, hi - lo)
    return common / max(1e-9, min(float(np.prod(a.size)), float(np.prod(b.size))))


def crease_at(cam, side: np.ndarray, point, reach: int = 1) -> bool:
    """Whether the side view has a crease line (a seam) at ``point``, within ``reach`` px."""
    u, v = np.rint(cam.project(np.array([point]))[0]).astype(int)
    column = side[max(0, v - reach):v + reach + 1, u]
    return bool(((column > DARK_MAX) & (column <= CREASE_MAX)).any())


def width_at(cam, side: np.ndarray, point) -> tuple[float, float] | None:
    """Width and centre x (mm) of the front face (-y, drawn at 170) through ``point``,
    on y = point.

    Its edges run through the crease pixels that bound the run of face pixels. The run
    ends at a crease or the dark, not at a pixel that noise took out of the face's band
    (at pixel noise 8 one pixel in 80 is: a 40 mm face read 24 mm, #12 round 17 u98);
    it must lie mostly in the band."""
    u, v = np.rint(cam.project(np.array([point]))[0]).astype(int)
    band = (side[v] >= FRONT_BAND[0]) & (side[v] <= FRONT_BAND[1])
    if not band[u]:
        return None
    row = side[v] > CREASE_MAX
    left, right = u, u
    while left > 0 and row[left - 1]:
        left -= 1
    while right + 1 < len(row) and row[right + 1]:
        right += 1
    if float(np.mean(band[left:right + 1])) < FACE_SHARE:
        return None
    ends = [cam.point_on_plane((x, float(v)), 1, point[1])[0]
            for x in (left - 1.0, right + 1.0)]
    return float(ends[1] - ends[0]), float(ends[0] + ends[1]) / 2.0
