"""A column read again as a stack when the blocks a task needs are missing (Sec. VII-A).

Two blocks of one footprint stacked are told from one tall block by the seam
across their front face (objects_stacks). A taller block standing in front can
hide that seam from the elevated side camera, and the top view shows only the
stack's top: the two views then fit a single block of the stack's size as well
as the stack (generated twins 1271, 2x: two 40 mm cubes behind a 40 x 40 x 80
column read as a second column). Only knowledge outside the images tells them
apart: how many blocks of each shape there are. In the execution workspace the
plan's objects count them; in the teach workspace the naming hint does (teach
name -> shape, the paper's names given by hand). When a count asks for blocks
the finder did not see, and a block of a shape it saw more of than counted is
as large as a stack of the missing ones, ``restack`` reads it as that stack,
provided the side view does not show its front face whole and unbroken where
each seam would be.

The same count settles a block measured between two shapes of one footprint: a
height read a pixel off (3.3 mm at the back of the table) made a 30 mm cube the
listed 35 mm one (helper round 19, r69, r83). A block of a shape seen more often
than counted that is within RENAME_PX of a missing shape, along every side, is
read as that shape (a stack of one), where that fits better than any stack.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from itertools import product

import numpy as np

from perception.vision.vfd import objects_rings as rims
from perception.vision.vfd.objects_match import STACK_MISMATCH_MM, FoundObject
from perception.vision.vfd.objects_stacks import seam_across

MOST_PIECES = 3  # stacks of up to this many blocks are tried
RENAME_PX = 1.25  # a block this near a missing shape on every side (side-view px) may be it


def restack(cam, side: np.ndarray, found: Sequence[FoundObject],
            needs: Mapping[str, int], shapes: Mapping[str, Sequence[float]]
            ) -> list[FoundObject]:
    """``found`` with surplus blocks read as stacks of the shapes ``needs`` lacks, while
    any lack remains and such a reading exists; else ``found`` as it is."""
    out = list(found)
    while True:
        have = Counter(f.shape for f in out)
        short = Counter({s: n - have[s] for s, n in needs.items() if n > have[s]})
        if not short:
            return out
        best = None
        for k, f in enumerate(out):
            if have[f.shape] <= needs.get(f.shape, 0):
                continue  # the task needs every block of this shape that was seen
            one = _one(cam, f, short, shapes)
            if one is not None and (best is None or one.mismatch < best[0]):
                best = (one.mismatch, k, [one])
            for names in _stacks(f, short, shapes):
                err = _fit(f, names, shapes)
                if best is not None and err >= best[0]:
                    continue
                pieces = _pieces(f, names, shapes)
                # the seams: the tops of all but the highest piece
                if all(_seam_unseen(cam, side, f, p.position[2] + p.size[2] / 2.0)
                       for p in pieces[:-1]):
                    best = (err, k, pieces)
        if best is None:
            return out
        _, k, pieces = best
        out[k:k + 1] = pieces


def _one(cam, f: FoundObject, short: Counter, shapes: Mapping[str, Sequence[float]]
         ) -> FoundObject | None:
    """``f`` read as the missing shape it is nearest, turned either way on the table, if
    within RENAME_PX of it along every side; its bottom stays where it was measured."""
    tol = RENAME_PX / max(1e-6, cam.mm_to_px(f.position))
    best = None
    for s in short:
        sx, sy, sz = (float(v) for v in shapes[s])
        for size in ((sx, sy, sz), (sy, sx, sz)):
            d = [abs(size[k] - f.size[k]) for k in range(3)]
            if max(d) <= tol and (best is None or sum(d) < best.mismatch):
                z = f.position[2] - f.size[2] / 2.0 + sz / 2.0
                best = FoundObject(s, (f.position[0], f.position[1], z), size, sum(d))
    return best


def _stacks(f: FoundObject, short: Counter, shapes: Mapping[str, Sequence[float]]
            ) -> list[tuple[str, ...]]:
    """Bottom-to-top shape sequences of 2..MOST_PIECES missing shapes, each as wide as
    ``f`` and together as tall (within STACK_MISMATCH_MM)."""
    fitting = [s for s in short if abs(shapes[s][0] - f.size[0]) + abs(shapes[s][1] - f.size[1])
               <= STACK_MISMATCH_MM]
    out = []
    for n in range(2, MOST_PIECES + 1):
        for names in product(fitting, repeat=n):
            if any(Counter(names)[s] > short[s] for s in names):
                continue
            if abs(sum(shapes[s][2] for s in names) - f.size[2]) <= STACK_MISMATCH_MM:
                out.append(names)
    return out


def _fit(f: FoundObject, names: Sequence[str], shapes: Mapping[str, Sequence[float]]) -> float:
    """How far the stack ``names`` is from ``f``'s measured size (mm, summed)."""
    return sum(abs(shapes[s][0] - f.size[0]) + abs(shapes[s][1] - f.size[1]) for s in names) \
        / len(names) + abs(sum(shapes[s][2] for s in names) - f.size[2])


def _pieces(f: FoundObject, names: Sequence[str], shapes: Mapping[str, Sequence[float]]
            ) -> list[FoundObject]:
    """The blocks ``names`` stacked on ``f``'s base under its top face's centre."""
    z = f.position[2] - f.size[2] / 2.0
    out = []
    for s in names:
        size = tuple(float(v) for v in shapes[s])
        out.append(FoundObject(s, (f.position[0], f.position[1], z + size[2] / 2.0), size,
                               _fit(f, names, shapes)))
        z += size[2]
    return out


def _seam_unseen(cam, side: np.ndarray, f: FoundObject, z: float) -> bool:
    """Whether the side view leaves a seam at height ``z`` possible on ``f``'s front face:
    it shows one, or something in front hides the face there. The face shown whole and
    as wide as ``f`` a pixel above and below, with no crease between, rules it out."""
    front = f.position[1] - f.size[1] / 2.0
    if seam_across(cam, side, f, front, z):
        return True
    mm = 1.0 / max(1e-6, cam.mm_to_px((f.position[0], front, z)))
    rows = [rims.width_at(cam, side, (f.position[0], front, z + d * mm)) for d in (-1, 0, 1)]
    whole = all(r is not None and abs(r[0] - f.size[0]) <= STACK_MISMATCH_MM for r in rows)
    return not (whole and not rims.crease_at(cam, side, (f.position[0], front, z), reach=0))
