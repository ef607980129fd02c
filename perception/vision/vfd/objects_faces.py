"""Top faces of finished structures: seen, measured (the monitor's look, objects_posed.py).

The object-finder pairs top faces with side-view heights as a whole and can pair
them wrongly; the faces themselves, in the top view, are sharp. These helpers
ask the top view directly: is a block's top face where it is expected (at its
height, with its footprint), and where exactly is it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import cv2
import numpy as np

from lbw_engine.model.geometry import footprints_meet
from perception.vision.vfd.objects import FoundObject
from perception.vision.vfd.objects_pieces import box_rect
from perception.vision.vfd.objects_rings import RING_HIDDEN_MM

SIZE_MM = 8.0  # a face's footprint this near the block's shape
TOP_MM = 6.0  # an uncovered block's top face measured this near its expected x, y
# A top face's measured centre moves a pose only when it differs by more than this: about
# a top-view pixel; over 318 looks, face centres were 1.0 mm off on average (p95 1.8 mm).
# Closer, the measurement cannot tell, and two aligned faces measured apart by noise would
# fail a 2 mm coplanarity the simulator passes (bench seed 1010 at 2x: 2.1 mm).
FACE_NOISE_MM = 2.5
# A partly covered block's visible top is checked where it is at least this wide both ways
# (a top-view face 4 px across), its face's edges within PART_TOL_MM (about a pixel and a
# half) of the visible part's and of the block's own.
PART_MM = 10.0
PART_TOL_MM = 4.0
Expected = tuple[str, Sequence[float], Sequence[float]]  # shape, centre, size


def tops_unseen(group: list[str], expected: Mapping[str, Expected],
                found: list[FoundObject], check: Any,
                covers: Sequence[tuple[Sequence[float], Sequence[float]]] = ()) -> list[str]:
    """The blocks of the group whose top face the top view does not show as expected.

    A block with nothing of the group above it must show its whole top face: the finder
    measured it there (its x, y are sharp, within TOP_MM), or the top view shows a top
    face of its footprint there at its height (``face_seen``). A block partly under
    others must show the rest (``part_seen``). ``covers``: (centre, size) of other blocks
    seen, which may lie over the group's (a beam pushed 30 mm back across the towers it
    bridged hides most of their tops: helper round 13, v80b)."""
    out = []
    for n in group:
        c, size = expected[n][1], expected[n][2]
        others = [expected[m][1:] for m in group if m != n] + list(covers)
        if _covered(c, size, others):
            if not part_seen(c, size, others, check):
                out.append(n)
        elif not _top_seen(c, size, found) and not face_seen(c, size, check):
            out.append(n)
    return out


def uncovered_or_part_seen(name: str, expected: Mapping[str, Expected], check: Any) -> bool:
    """A block posed alone (hidden, or in place of a reading) when others are expected
    over part of it: the rest of its top face must show (``part_seen``). Its silhouettes
    alone cannot tell: the blocks behind and under it fill the same pixels."""
    c, size = expected[name][1], expected[name][2]
    others = [e[1:] for m, e in expected.items() if m != name]
    return not _covered(c, size, others) or part_seen(c, size, others, check)


def top_missing(name: str, expected: Mapping[str, Expected], boxes: Sequence[Any],
                check: Any) -> bool:
    """A block with nothing expected over it, whose top face no taller box hides from the
    top camera (their images cover under half of it), and the top view shows no face
    there: it is not there, however little of the views it would fill (a 10 mm cube,
    3 px across, fits the silhouettes' tolerance: helper round 12, 71)."""
    c, size = expected[name][1], expected[name][2]
    if _covered(c, size, [e[1:] for m, e in expected.items() if m != name]) or \
            face_seen(c, size, check):
        return False
    cam = check.cameras["top"]
    top = c[2] + size[2] / 2.0
    u0, v0, u1, v1 = box_rect(cam, (c[0], c[1], top), (size[0], size[1], 0.0))
    area = max(1e-9, (u1 - u0) * (v1 - v0))
    hidden = 0.0
    for b in boxes:
        if b is None or b.position[2] + b.size[2] / 2.0 <= top + 1.0:
            continue
        a0, b0, a1, b1 = box_rect(cam, b.position, b.size)
        hidden += max(0.0, min(u1, a1) - max(u0, a0)) * \
            max(0.0, min(v1, b1) - max(v0, b0)) / area  # overlaps summed: at most more
    return hidden < 0.5


def part_seen(c: Sequence[float], size: Sequence[float],
              others: Sequence[tuple[Sequence[float], Sequence[float]]], check: Any) -> bool:
    """The parts of this block's top face that the taller ``others`` (centre, size) leave
    in the top camera's sight are top faces of the top view: each part at least PART_MM
    wide both ways (slivers left out) is spanned by the faces that, put at this block's
    top height, lie within the block's footprint and on the part. Silhouettes cannot
    show a partly covered block gone: the blocks behind and under it fill its pixels in
    both views (a pyramid's second-row cube taken from under half of the top cube, fault
    bench seed 7010); the face its strip showed at its height is what is missing."""
    top = c[2] + size[2] / 2.0
    x0, y0 = c[0] - size[0] / 2.0, c[1] - size[1] / 2.0
    shown = np.ones((max(1, math.ceil(size[1])), max(1, math.ceil(size[0]))), np.uint8)
    for oc, os in others:
        if oc[2] + os[2] / 2.0 <= top + 1.0:
            continue
        sx0, sy0, sx1, sy1 = check.finder.footprint(box_rect(check.cameras["top"], oc, os), top)
        shown[max(0, math.floor(sy0 - y0)):max(0, math.ceil(sy1 - y0)),
              max(0, math.floor(sx0 - x0)):max(0, math.ceil(sx1 - x0))] = 0
    # Slivers thinner than PART_MM (a strip beside a cover, where creases take the pixels)
    # are not looked for; outside the footprint counts as hidden, or a sliver along the
    # block's edge would be kept.
    k = int(PART_MM)
    shown = cv2.morphologyEx(shown, cv2.MORPH_OPEN, np.ones((k, k), np.uint8),
                             borderType=cv2.BORDER_CONSTANT, borderValue=0)
    n, _, stats, _ = cv2.connectedComponentsWithStats(shown, connectivity=4)
    t = PART_TOL_MM
    mine = [f for f in (check.finder.footprint(rect, top) for rect in check.faces)
            if f[0] >= x0 - t and f[1] >= y0 - t and f[2] <= x0 + size[0] + t
            and f[3] <= y0 + size[1] + t]  # faces that, at this height, lie on the block
    for px, py, pw, ph, _ in stats[1:n]:
        if pw < PART_MM or ph < PART_MM:
            continue
        bx0, by0, bx1, by1 = x0 + px, y0 + py, x0 + px + pw, y0 + py + ph
        # One visible part may show as several faces (pixel noise cuts a narrow ring).
        on = [f for f in mine if f[0] < bx1 and f[2] > bx0 and f[1] < by1 and f[3] > by0]
        if not on or min(f[0] for f in on) > bx0 + t or min(f[1] for f in on) > by0 + t \
                or max(f[2] for f in on) < bx1 - t or max(f[3] for f in on) < by1 - t:
            return False
    return True


def _covered(c: Sequence[float], size: Sequence[float],
             others: Sequence[tuple[Sequence[float], Sequence[float]]]) -> bool:
    """Whether any of ``others`` (centre, size) stands higher over this block's footprint."""
    return any(oc[2] > c[2] and footprints_meet(oc, os, c, size, tol=0.0) for oc, os in others)


def face_seen(c: Sequence[float], size: Sequence[float], check: Any) -> bool:
    """A top face of the top view, put at this block's top height, has its footprint and
    lies where its top is (within TOP_MM). The finder's reading can miss it when it pairs
    faces with side-view heights wrongly (a brick on a disc at 4x pixel noise: the disc's
    visible ring was taken for the brick, 9 mm off); the face itself is plain to see."""
    return _face_at(c, size, check, TOP_MM) is not None


def _face_at(c: Sequence[float], size: Sequence[float], check: Any, gate: float
             ) -> tuple[float, float] | None:
    """The x, y centre of the nearest top face of the top view that, put at this block's
    top height, has its footprint and lies within ``gate`` of its x, y; None if none."""
    top = c[2] + size[2] / 2.0
    best, near = None, gate
    for rect in check.faces:
        x0, y0, x1, y1 = check.finder.footprint(rect, top)
        x, y = (x0 + x1) / 2.0, (y0 + y1) / 2.0
        off = max(abs(x - c[0]), abs(y - c[1]))
        if off <= near and abs(x1 - x0 - size[0]) + abs(y1 - y0 - size[1]) <= SIZE_MM:
            best, near = (x, y), off
    return best


def measure_tops(boxes: list, named: dict[str, int], check: Any) -> None:
    """Named blocks with nothing on them take the x, y of their top face as the top view
    measures it (at their height), not the expected pose that explained the views: the
    silhouette test forgives a few mm (a pixel is about 2.5 mm, and the bands along the
    outlines are not counted), so a top dropped 5 mm off its goal passed as on it.
    A face is looked for within half the block's narrower side of its expected x, y (a
    12 mm cube's neighbour of its shape is nearer than 15 mm); it must be nearer to
    this block than to any other uncovered one."""
    idx = list(named.values())
    uncovered = [i for i in idx if not _covered(boxes[i].position, boxes[i].size, [
        (boxes[j].position, boxes[j].size) for j in idx if j != i])]
    moved = {}
    for i in uncovered:
        b = boxes[i]
        xy = _face_at(b.position, b.size, check, min(b.size[:2]) / 2.0)
        mine = xy is not None and min(uncovered, key=lambda j: math.dist(
            boxes[j].position[:2], xy)) == i
        if mine and max(abs(xy[0] - b.position[0]), abs(xy[1] - b.position[1])) > FACE_NOISE_MM:
            moved[i] = replace(b, position=(xy[0], xy[1], b.position[2]))
    for i, b in moved.items():
        boxes[i] = b


def _top_seen(c: Sequence[float], size: Sequence[float], found: list[FoundObject]) -> bool:
    """The finder measured this top face: one reading centred on it (within TOP_MM), or
    readings at its height that together span its footprint. A top over a gap between
    two supports is cut in two by the supports' edges and read as two columns. A reading
    centred there is this face only at its height and about its size, thin rings merged
    in (a 40 mm block's reading took for a 10 mm cube expected on its centre, which the
    fault had taken away: helper round 12, 71, cameras true and ground truth false)."""
    top = c[2] + size[2] / 2.0
    if any(abs(f.position[0] - c[0]) <= TOP_MM and abs(f.position[1] - c[1]) <= TOP_MM
           and abs(f.position[2] + f.size[2] / 2.0 - top) <= SIZE_MM
           and all(abs(f.size[k] - size[k]) <= SIZE_MM + 2 * RING_HIDDEN_MM for k in (0, 1))
           for f in found):
        return True
    parts = [f for f in found if abs(f.position[2] + f.size[2] / 2.0 - top) <= SIZE_MM
             and all(abs(f.position[k] - c[k]) < (f.size[k] + size[k]) / 2.0 for k in (0, 1))]
    return len(parts) > 1 and all(
        min(f.position[k] - f.size[k] / 2.0 for f in parts) <= c[k] - size[k] / 2.0 + TOP_MM
        and max(f.position[k] + f.size[k] / 2.0 for f in parts) >= c[k] + size[k] / 2.0 - TOP_MM
        for k in (0, 1))
