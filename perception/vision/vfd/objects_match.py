"""Object-finder correspondence (which side-view top face belongs to which top face) and the
small rectangle and shape-database helpers the finder shares.

Each top-view face proposes a few (score, height, side face) candidates (see
``Columns.candidates``). A side-view top face is the top of one block only,
so pairs are taken best first. That alone can still pair wrongly: a block's
footprint lifted to a wrong height lands on the top face of a block in front
of it on nearly the same view line, and the two fits can score alike. The
pairing is therefore checked against both whole views (Sec. III-B uses the two
views together): the boxes [footprint] x [0, h] of a pairing, drawn as
silhouettes, must reproduce the non-dark pixels of the top and side images;
alternatives that reproduce them better replace the greedy choice.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

Candidate = tuple[float, float, int]  # (score, height mm, side-view face label)
AMBIGUOUS = 0.15  # a candidate this close to a face's best score is a real alternative
MIN_GAIN_PX = 12  # fewer wrong pixels than this is not evidence (edges, occlusion)
STACK_MISMATCH_MM = 8.0  # a column this far from every shape may be a stack of two


@dataclass(frozen=True)
class FoundObject:
    """A block recognized in the initial state."""

    shape: str
    position: tuple[float, float, float]  # box centre, mm
    size: tuple[float, float, float]  # measured extents, mm
    mismatch: float  # mm, summed |measured - database size|


def greedy(cands: Sequence[Sequence[Candidate]], forced: dict[int, Candidate]
           ) -> dict[int, tuple[float, float]]:
    """Faces -> (height, score): ``forced`` choices first, then the best free claims."""
    out: dict[int, tuple[float, float]] = {}
    taken: set[int] = set()
    for k, (sc, h, lab) in forced.items():
        out[k] = (h, sc)
        taken.add(lab)
    claims = sorted(((sc, k, lab, h) for k, cs in enumerate(cands) if k not in forced
                     for sc, h, lab in cs), reverse=True)
    for sc, k, lab, h in claims:
        if k not in out and lab not in taken:
            out[k] = (h, sc)
            taken.add(lab)
    return out


def assign(cands: Sequence[Sequence[Candidate]], cost: Callable[[dict[int, tuple]], int],
           doubtful: Callable[[dict[int, tuple]], int] | None = None,
           passes: int = 3) -> dict[int, tuple[float, float]]:
    """The pairing whose boxes best explain both views, starting from the greedy one.

    ``cost`` maps a pairing {face: (height, score)} to the number of pixels its
    silhouettes get wrong. Each pass tries every face's other candidates that
    fit the side view nearly as well as its best one (the faces they displace
    take their best remaining claim) and keeps the best improvement as a fixed
    choice. Only near-ties are reopened (a face's candidates within AMBIGUOUS of
    its best, on side faces no other face holds by a claim clearly better): the
    silhouettes of boxes standing on the table are a coarse model where blocks
    hide each other. On a stack of 40, 30 and 20 mm blocks the 30 mm ring's
    outline (0.61) took the top face's side face from the 20 mm block's own face
    (0.95) for 14 fewer wrong pixels, and the top block was read as a ring's
    piece (helper round 15, 09).

    Where a pairing draws the views no worse but not clearly better, ``doubtful``
    (the number of its columns no shape or stack of shapes is as high) decides:
    a block standing just behind a tower, its face lifted to the tower's top, is
    hidden there as well as the tower's own face is (helper round 14, AD). A pairing
    that draws them worse, by however little, is not taken for that: a cube's column
    read 2 mm short of cube + block lost to the block's outline, 12 pixels worse
    (generated rearrange 1073).
    """
    forced: dict[int, Candidate] = {}
    best = greedy(cands, forced)
    labels = [lab for cs in cands for _, _, lab in cs]
    if all(len(cs) < 2 for cs in cands) and len(set(labels)) == len(labels):
        return best

    def held(pairing: dict[int, tuple[float, float]], but: int) -> dict[int, float]:
        """Side face -> the score of the claim on it that ``pairing`` took (but face's)."""
        return {lab: sc for j, (h, s) in pairing.items() if j != but
                for sc, hh, lab in cands[j] if (hh, sc) == (h, s)}

    best_cost = cost(best)
    best_doubt = doubtful(best) if doubtful else 0
    for _ in range(passes):
        improved = None
        for k, cs in enumerate(cands):
            if k in forced:
                continue
            for c in cs:
                if c[0] < cs[0][0] - AMBIGUOUS or best.get(k, (None,))[0] == c[1]:
                    continue
                if c[0] < held(best, k).get(c[2], 0.0) - AMBIGUOUS:
                    continue  # another face holds that side face by a clear margin
                trial = greedy(cands, {**forced, k: c})
                tc = cost(trial)
                td = doubtful(trial) if doubtful and tc <= best_cost else 0
                if tc < best_cost - MIN_GAIN_PX or (td < best_doubt and tc <= best_cost):
                    best, best_cost, best_doubt, improved = trial, tc, td, (k, c)
        if improved is None:
            break
        forced[improved[0]] = improved[1]
    return best


class SilhouetteCheck:
    """Counts the pixels a set of boxes gets wrong against both views' non-dark masks."""

    def __init__(self, cameras: dict, solid: dict[str, np.ndarray]) -> None:
        """``solid``: per camera name, the boolean mask of non-dark pixels."""
        self.cameras = cameras
        self.solid = {name: m.astype(np.uint8) for name, m in solid.items()}

    def wrong_pixels(self, boxes: Sequence[tuple[float, float, float, float, float]]) -> int:
        """Pixels where boxes (x0, y0, x1, y1, h) on the table disagree with the views."""
        total = 0
        for name, actual in self.solid.items():
            cam = self.cameras[name]
            drawn = np.zeros_like(actual)
            for x0, y0, x1, y1, h in boxes:
                corners = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1)
                                    for z in (0.0, h)])
                uv = cam.project(corners)
                hull = cv2.convexHull(np.rint(uv * 16).astype(np.int32))
                cv2.fillConvexPoly(drawn, hull, 1, cv2.LINE_8, 4)
            total += int(cv2.countNonZero(cv2.bitwise_xor(drawn, actual)))
        return total


def frames(outer, inner, tol: float = 1.5) -> bool:
    """Whether pixel rectangle ``outer`` encloses ``inner`` (and is larger)."""
    area = (outer[2] - outer[0]) * (outer[3] - outer[1])
    return (outer[0] <= inner[0] + tol and outer[1] <= inner[1] + tol and
            outer[2] >= inner[2] - tol and outer[3] >= inner[3] - tol and
            area > (inner[2] - inner[0]) * (inner[3] - inner[1]))


def nearest(shapes: Mapping[str, Sequence[float]], size: np.ndarray) -> tuple[str, float]:
    """The database shape whose size is closest to ``size`` (summed absolute error)."""
    if not shapes:
        return "unknown", float("inf")
    errs = {name: float(np.abs(np.asarray(s, float) - size).sum()) for name, s in shapes.items()}
    name = min(errs, key=errs.get)
    return name, errs[name]
