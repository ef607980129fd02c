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

from perception.vision.vfd.base import Region3D, region_mask, regions_mask
from perception.vision.vfd.objects_rings import Box, heights_of, holds_centre
from perception.vision.vfd.resources import Window

HIDDEN_SHARE = 0.6  # of a top face's side-view image inside nearer blocks' images: unseen
APART_MM = 10.0  # a nearer block stands this far in front: not a ring of the same stack
# ... or only this far, before a face whose height the column search gave: a 10 mm cube
# 6 mm behind a 60 mm block read 55 mm tall (helper round 11, v53a); a measured face
# keeps the wider gap (the top of a stack of three sizes, a ring strip 10 mm in front)
SEARCHED_APART_MM = 3.0
FIT_MM = 6.0  # a searched height this near a shape's (its footprint's) is that shape's

Footprint = Callable[[tuple, float], tuple[float, float, float, float]]


def unseen_heights(boxes: list[Box], cam, size: tuple[int, int], footprint: Footprint,
                   shapes: Mapping[str, Sequence[float]],
                   measured: frozenset[int] | set[int] = frozenset()) -> list[Box]:
    """``boxes`` with each top face that the blocks nearer the side camera hide at its
    height lowered to the height of the shape its footprint names, where that hides it
    too. A box whose height no side-view top face of its own gave (not in ``measured``:
    the column search's) is lowered too when the nearer blocks hide its whole column: the
    search climbed their silhouette to their top edge, where the face shows a little
    (helper round 11, v53g: a 10 mm cube 30 mm behind a 60 mm block read 51 mm tall).
    ``size``: the side image's (width, height)."""
    whole = Window("side", 0, 0, size[0], size[1])
    out = list(boxes)
    for k, (h, fp, rect) in enumerate(boxes):
        if k not in measured:
            lower = _in_front_of(k, boxes, cam, whole, footprint, shapes)
            if lower is not None:
                out[k] = lower
                continue
        apart = APART_MM if k in measured else SEARCHED_APART_MM
        nearer = [b for j, b in enumerate(boxes) if j != k and b[1][3] < fp[1] - apart]
        if not nearer or any(j != k and (holds_centre(r, rect) or holds_centre(rect, r))
                             for j, (_, _, r) in enumerate(boxes)):
            continue  # nothing in front; or a face of a stack, whose column the seams read
        front = _columns(cam, nearer, whole)
        if not _hidden(cam, whole, front, footprint(rect, h), h) and (
                k in measured or not _hidden(cam, whole, front, footprint(rect, h), h, 0.0)):
            continue
        for z in sorted((t for t in heights_of(fp, shapes) if t < h - 3.0), reverse=True):
            if _hidden(cam, whole, front, footprint(rect, z), z):
                out[k] = (z, footprint(rect, z), rect)
                break
    return out


def _in_front_of(k: int, boxes: list[Box], cam, whole: Window, footprint: Footprint,
                 shapes: Mapping[str, Sequence[float]]) -> Box | None:
    """Box ``k`` (a searched height) lowered to a height of a shape its footprint names,
    when no such shape is as tall as the search found and the column above that height
    lies on the image of blocks behind it: the search ran on up their faces to their top
    edge (helper round 12, v26b: a 10 mm cube 25 mm in front of an 80 mm pillar read
    100 mm tall, then split into a phantom cube on the pillar). None: keep it."""
    h, fp, rect = boxes[k]
    heights = heights_of(fp, shapes)
    stacked = [t + float(s[2]) for t in heights for s in shapes.values()]  # on one block
    if not heights or any(abs(t - h) <= FIT_MM for t in [*heights, *stacked]):
        return None  # its shape's height, or a stack of two (a brick on a brick)
    behind = [b for j, b in enumerate(boxes) if j != k and b[1][1] >= fp[3]]
    if not behind:
        return None
    back = _columns(cam, behind, whole)
    for z in sorted((t for t in heights if t < h - 3.0), reverse=True):
        if _hidden(cam, whole, back, footprint(rect, h), h, z):
            return (z, footprint(rect, z), rect)
    return None


def _columns(cam, boxes: Sequence[Box], window: Window):
    """The mask of ``boxes``' images, each a column from the table up to its top face."""
    return regions_mask(cam, [Region3D((a0, b0, 0.0), (a1, b1, g))
                              for g, (a0, b0, a1, b1), _ in boxes], window)


def _hidden(cam, window: Window, front, fp: tuple[float, float, float, float], z: float,
            low: float | None = None) -> bool:
    """Whether ``front`` (a mask of the blocks in front) hides the top face ``fp`` at ``z``
    (with ``low``: the column from there up to it)."""
    face = region_mask(cam, Region3D((fp[0], fp[1], z if low is None else low),
                                     (fp[2], fp[3], z)), window)
    n = int(face.sum())
    return n > 0 and float((face & front).sum()) / n >= HIDDEN_SHARE
