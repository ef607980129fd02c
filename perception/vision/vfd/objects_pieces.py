"""Which of the object-finder's readings are a block's pieces (objects_posed.py).

A block the finder misread may come out as a column, rings, a stack of two, or
a reading put elsewhere because its face was paired with a wrong height. When
the monitor poses the block, those readings must go with it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from lbw_engine.model.geometry import footprints_meet
from perception.vision.camera import Camera
from perception.vision.vfd.objects import FoundObject

GATE_MM = 15.0  # a top face this near an expected block's (in x, y) may be that block
SIZE_MM = 8.0  # and its footprint this near the block's shape
SHIFT_MM = 4.0  # a posed block read farther off than this is tried where it was read
SHIFT_PX = 1.5  # ... if that moves its image in the side view this far (px)


def box_rect(cam: Camera, center: Sequence[float], size: Sequence[float]
          ) -> tuple[float, float, float, float]:
    """The image rectangle (u0, v0, u1, v1) around a box's projection."""
    corners = np.array([[center[k] + s * size[k] / 2.0 for k, s in enumerate((a, b, c))]
                        for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)])
    uv = cam.project(corners)
    return (*uv.min(axis=0), *uv.max(axis=0))


def reading_of(boxes: list, free: list[int], center: Sequence[float],
             size: Sequence[float]) -> list[int]:
    """The one found block whose top face is where this block's would be."""
    return [i for i in free
            if abs(boxes[i].position[0] - center[0]) <= GATE_MM
            and abs(boxes[i].position[1] - center[1]) <= GATE_MM
            and abs(boxes[i].size[0] - size[0]) + abs(boxes[i].size[1] - size[1]) <= SIZE_MM][:1]


def pieces_of(boxes: list, free: list[int], center: Sequence[float], size: Sequence[float],
            any_size: bool = False, any_height: bool = False, top_cam: Camera | None = None
            ) -> list[int]:
    """Found blocks within this block's footprint, no larger and not above it: its pieces.
    With ``top_cam``, also any reading made of this block's pixels in the top view (its
    box's image mostly on this one's): a face paired with a wrong height is put
    elsewhere in x, y (a 15 mm pillar with another behind it on the side camera's line of
    sight was read 13 mm off and 74 mm too tall, bench seed 1015)."""
    top = center[2] + size[2] / 2.0
    return [i for i in free
            if (all(abs(boxes[i].position[k] - center[k]) <= size[k] / 2.0 for k in (0, 1))
                or (top_cam is not None and _same_pixels(top_cam, boxes[i], center, size)))
            and (any_height or boxes[i].position[2] - boxes[i].size[2] / 2.0 < top - SIZE_MM)
            and (any_size or all(boxes[i].size[k] <= size[k] + SIZE_MM for k in (0, 1)))]


def with_columns_under(boxes: list, parts: list[int], named: dict[str, int]) -> list[int]:
    """``parts`` and the free readings each stands on (its footprint over theirs, its
    bottom at their top within SIZE_MM), transitively: the finder split the column under
    a misread face into a stack, and its lower piece is that face's reading too."""
    out, grew = list(parts), True
    while grew:
        grew = False
        for i, b in enumerate(boxes):
            if b is None or i in out or i in named.values():
                continue
            top = b.position[2] + b.size[2] / 2.0
            if any(abs(boxes[j].position[2] - boxes[j].size[2] / 2.0 - top) <= SIZE_MM
                   and footprints_meet(boxes[j].position, boxes[j].size, b.position,
                                       b.size, tol=0.0)
                   for j in out):
                out.append(i)
                grew = True
    return sorted(out)


def _same_pixels(cam: Camera, found: FoundObject, center: Sequence[float],
                 size: Sequence[float]) -> bool:
    """Whether a reading's box, in the top view, lies mostly (over half of the smaller
    image rectangle) on this block's: the reading was made of this block's pixels."""
    a, b = box_rect(cam, found.position, found.size), box_rect(cam, center, size)
    common = max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * \
        max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    smaller = min((a[2] - a[0]) * (a[3] - a[1]), (b[2] - b[0]) * (b[3] - b[1]))
    return smaller > 0 and common > 0.5 * smaller


def above(b: FoundObject, trial: Sequence[FoundObject], tol: float) -> bool:
    """Whether a reading lies wholly above the blocks of ``trial`` whose footprints it meets
    (its bottom no more than ``tol``, nor a quarter of the block's height, under their
    tops: a 12 mm cube's own reading, its height misread by 8 mm, is not on it)."""
    low = b.position[2] - b.size[2] / 2.0
    met = [t for t in trial if footprints_meet(b.position, b.size, t.position, t.size, tol=0.0)]
    return bool(met) and all(low >= t.position[2] + t.size[2] / 2.0 - min(tol, t.size[2] / 4.0)
                             for t in met)


def images_of(cameras: Mapping[str, Camera], found: FoundObject
              ) -> dict[str, tuple[float, float, float, float]]:
    """A box's image rectangle in each camera."""
    return {name: box_rect(cam, found.position, found.size) for name, cam in cameras.items()}


def overlaps_images(cameras: Mapping[str, Camera], found: FoundObject,
                    rects: Sequence[Mapping[str, tuple[float, float, float, float]]]) -> bool:
    """Whether a reading's box meets one of the blocks (their ``images_of``) in both views."""
    mine = images_of(cameras, found)
    return any(all(meet(mine[name], r[name]) for name in mine) for r in rects)


def meet(a: Sequence[float], b: Sequence[float]) -> bool:
    """Whether two image rectangles (u0, v0, u1, v1) overlap."""
    return min(a[2], b[2]) > max(a[0], b[0]) and min(a[3], b[3]) > max(a[1], b[1])


def shifted(boxes: list, named: Mapping[str, int], found: Sequence[FoundObject],
            cost: Callable[[], int], worse: int, side: Camera) -> None:
    """Posed blocks moved to where the finder read them, when the views say so.

    A block posed with its structure (``explain``) keeps its expected pose while the
    views near it agree to within a pixel's band, and a block under another shows too
    little of itself to move that band: a tower's middle cube slid 7 mm (2.3 pixels)
    passed as in place, though the finder had read it 7 mm off (helper round 15's AN).
    Where a reading of the posed block's shape and height lies more than SHIFT_MM off
    it, the block is tried there, along either axis or both; a trial stands only if it
    explains the views by more than ``worse`` wrong pixels better than the pose, and
    moves the block's image in the ``side`` camera by SHIFT_PX or more: a block under
    others shows only there, and a move toward or away from that camera is a fraction
    of a pixel (a cube under a plate, read 5 mm nearer than it stood, fit the views 15
    pixels better there: bench 1201, a false detection and a repair that could not be
    done)."""
    base = cost()
    poses = {i: boxes[i] for i in named.values()}
    for _, i in sorted(named.items()):  # in name order
        posed = boxes[i]
        for r in found:
            d = [r.position[k] - posed.position[k] for k in range(2)]
            # (``reading_of`` holds it within GATE_MM in x and y)
            if not (r.shape == posed.shape and SHIFT_MM < max(map(abs, d))
                    and abs(r.position[2] - posed.position[2]) <= SIZE_MM
                    and reading_of([r], [0], posed.position, posed.size)) or any(
                        j != i and math.dist(r.position, p.position)
                        < math.dist(r.position, posed.position) for j, p in poses.items()):
                continue  # not this block's reading, or nearer another posed block
            best = None
            for dx, dy in ((d[0], 0.0), (0.0, d[1]), tuple(d)):
                to = np.add(posed.position, (dx, dy, 0.0))
                uv = side.project(np.array([posed.position, to], float))
                if max(abs(dx), abs(dy)) <= SHIFT_MM or \
                        float(np.linalg.norm(uv[1] - uv[0])) < SHIFT_PX:
                    continue
                boxes[i] = FoundObject(posed.shape, tuple(map(float, to)), posed.size,
                                       posed.mismatch)
                trial = cost()
                if trial < base - worse and (best is None or trial < best[0]):
                    best = (trial, boxes[i])
            boxes[i] = posed if best is None else best[1]
            if best is not None:
                base = best[0]
                break
