"""Posed blocks moved a few millimetres: tried, not read (objects_posed.py).

The monitor poses each block where it expects it, and the silhouette test
forgives what a pixel's band along the outlines hides; ``shifted`` moves a
block only to where the finder read it. A block under or behind others has no
reading: its top face is covered and, in the side view, another block stands
in front of it. Slid 6-12 mm, it still shows: a strip of its top face between
the blocks over it, or a sliver of its front beside the block in front (the
bottom-middle cube of a pyramid slid 7 mm along x, fault bench seed 9009: the
ground truth saw it off, the cameras passed it). So each posed block is tried
along x and along y, every STEP_MM up to REACH_MM, with the views compared
off strips one pixel thin (``Silhouettes.moves``).

Along an axis, the moves that explain the views best form a run (a strip
narrower than a pixel cannot tell them apart); the block's place is the run's
middle. It is moved there when that is MOVE_MM or more off and explains the
views better than the pose by more than ``worse`` pixels in a view where the
move shifts the block's image by SHIFT_PX or more: a move toward or away from
the side camera changes the block's image there by a fraction of a pixel (the
15-pixel gain of bench 1201, ``objects_pieces.shifted``). The block of the
largest gain moves first; then all are tried again (a tower's bottom cube slid,
the cubes on it dragged part of the way).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from perception.vision.vfd.objects_pieces import GATE_MM, SHIFT_PX

STEP_MM = 1.5  # the moves tried along each axis: every STEP_MM ...
REACH_MM = 12.0  # ... up to this far each way
MOVE_MM = 3.0  # a run's middle nearer than this to the pose is the pose (rounding)


def nudged(boxes: list, named: Mapping[str, int], check, worse: int) -> None:
    """Move named blocks (in place) where the views show them slid, as the module says; at
    most GATE_MM from where they were posed."""
    start = {i: boxes[i].position for i in named.values()}
    for _ in range(2 * len(start)):
        best = None
        # the lowest first: of blocks one over another that explain the views alike, the
        # one under the others slid (what rests on a block rides along when it slides)
        for i in sorted(start, key=lambda i: (boxes[i].position[2], boxes[i].position)):
            move = _move(boxes, i, check, worse)
            if move is not None and float(np.hypot(*np.subtract(
                    move[1], start[i])[:2])) <= GATE_MM and (best is None or move[0] > best[0]):
                best = (move[0], move[1], i)
        if best is None:
            return
        boxes[best[2]] = replace(boxes[best[2]], position=best[1])


def _move(boxes: list, i: int, check, worse: int) -> tuple[int, tuple] | None:
    """The gain and the new centre of block ``i``'s best move along x or y, or None."""
    shown = [(b.position, b.size) for b in boxes if b is not None]
    k = sum(1 for b in boxes[:i] if b is not None)
    grid = np.arange(-REACH_MM, REACH_MM + STEP_MM / 2, STEP_MM)
    p0 = np.asarray(boxes[i].position, float)
    best = None
    for axis in (0, 1):
        shifts = [(g, 0.0) if axis == 0 else (0.0, g) for g in grid]
        costs = check.moves(shown, k, [(0.0, 0.0)] + shifts)
        here, costs = costs[0], costs[1:]
        d = _middle(grid, [sum(c.values()) for c in costs])
        if abs(d) < MOVE_MM:
            continue
        at = costs[int(np.argmin(np.abs(grid - d)))]
        to = p0 + ((d, 0.0, 0.0) if axis == 0 else (0.0, d, 0.0))
        gain = max((here[v] - at[v] for v in at
                    if _image_move(check.cameras[v], p0, to) >= SHIFT_PX), default=0)
        if gain > worse and (best is None or gain > best[0]):
            best = (gain, (float(to[0]), float(to[1]), float(to[2])))
    return best


def _middle(grid: np.ndarray, totals: Sequence[int]) -> float:
    """The middle of the run of least totals around the least one nearest the pose."""
    least = min(totals)
    j = min((j for j, t in enumerate(totals) if t == least), key=lambda j: abs(grid[j]))
    lo = hi = j
    while lo > 0 and totals[lo - 1] == least:
        lo -= 1
    while hi < len(totals) - 1 and totals[hi + 1] == least:
        hi += 1
    return float(grid[lo] + grid[hi]) / 2.0


def _image_move(cam, a: Sequence[float], b: Sequence[float]) -> float:
    """How far (px) a point moving from ``a`` to ``b`` moves in the camera's image."""
    uv = cam.project(np.array([a, b], float))
    return float(np.linalg.norm(uv[1] - uv[0]))
