"""Sil-finder and the guided visual search (Sec. III-C2, III-E, Fig. 6).

The sil-finder watches a projected 3-D region in both views and reports the
centre of mass of the binarized block silhouette inside its windows (GGE). The
visual search sets the region at the hand (the default 50 x 50 x 45 mm prism,
footnote 6, or the held object's box), steps it straight down by its own height
(footnote 8) up to min(steps to the table, 4) times (footnote 10), and returns
the 3-D position of the first silhouette found. The caller confirms it against
the environment model and then places the snapshot region (Fig. 6(3)) with
``snapshot_region``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from perception.vision.frames import Frame
from perception.vision.vfd.base import (
    VFD,
    Region3D,
    centroid,
    region_mask,
    regions_mask,
    silhouette,
)

DEFAULT_REGION = (50.0, 50.0, 45.0)  # mm, footnote 6
CYCLE_LIMIT = 4  # footnote 10
MIN_AREA = 0.08  # fraction of a window that must be silhouette to count as found
EXPECTED_SHARE = 0.3  # ... or this share of the smallest expected object's outline, if less


class SilFinder(VFD):
    """Centre of mass of block silhouette pixels inside the attention region's windows."""

    min_area = MIN_AREA
    stereo = False  # whether the last silhouette was confirmed by both views

    def process(self, frame: Frame) -> None:
        """Look for a silhouette in the windows of the current region."""
        pos = self.look(frame)
        if pos is not None:
            self._target, self._found = pos, True

    def look(self, frame: Frame, exclude: Sequence[Region3D] = (),
             expect: Sequence[float] | None = None) -> np.ndarray | None:
        """3-D position of the silhouette inside the region on ``frame``, or None.

        Only pixels inside the region's projected outline count; the outlines of
        the ``exclude`` boxes (the held object, known to the environment model)
        are left out, since from both cameras it hangs over the place searched.
        A silhouette counts when it fills ``min_area`` of that outline, or, with
        ``expect`` (the size of the smallest object that may be there),
        EXPECTED_SHARE of the outline of such an object at the region's centre if
        that is less: a 12 mm cube fills 5 % of the default 50 x 50 x 45 mm region
        (issue #12 class 3).
        """
        pts = {}
        for view in ("top", "side"):
            (w,) = self.windows[view]
            cam = self.cameras[view]
            sub = w.read(frame.view(view))
            inside = region_mask(cam, self.region, w) & ~regions_mask(cam, exclude, w)
            need = self.min_area * max(1, int(inside.sum()))
            if expect is not None:
                small = region_mask(cam, Region3D.around(self.region.center, expect), w)
                need = min(need, EXPECTED_SHARE * max(1, int(small.sum())))
            c = centroid(silhouette(sub) & inside)
            if c is not None and c[2] >= need:
                pts[view] = (w.x0 + c[0], w.y0 + c[1])
        self.stereo = False
        if "side" not in pts:
            return None  # from above, the hand hides what lies under it: the side view decides
        if "top" in pts:
            p = self.triangulate(pts["top"], pts["side"])
            if np.all(p >= np.asarray(self.region.lo) - 30) and \
                    np.all(p <= np.asarray(self.region.hi) + 30):
                self.stereo = True
                return p
        # Monocular fallback: the side view line at the region's depth (a block in front
        # of or behind the region can answer; the environment model must confirm it).
        return self.cameras["side"].point_on_plane(pts["side"], 1, float(self.region.center[1]))


@dataclass
class SearchResult:
    """Outcome of one guided visual search."""

    found: bool
    position: np.ndarray | None
    cycles: int
    regions: list[Region3D] = field(default_factory=list)
    stereo: bool = False  # seen in both views (else the side view alone, at the region depth)


def search_start(hand: Sequence[float], held_size: Sequence[float] | None = None) -> Region3D:
    """Initial attention region (Fig. 6(1)): default prism or the held object's box."""
    if held_size is None:
        return Region3D.around(hand, DEFAULT_REGION)
    # The held object hangs between the fingers; its box is centred under the palm.
    return Region3D.around(hand, held_size)


def visual_search(finder: SilFinder, frame: Frame, hand: Sequence[float],
                  held_size: Sequence[float] | None = None,
                  held_center: Sequence[float] | None = None,
                  limit: int = CYCLE_LIMIT) -> SearchResult:
    """Guided visual search on the current frame (Sec. III-E, steps 1 and 2)."""
    start = search_start(held_center if held_center is not None else hand, held_size)
    step = float(start.size[2])  # footnote 8: straight down by the region's height
    to_table = max(0, math.ceil(start.lo[2] / step))
    cycles = min(to_table, limit)
    first = 1 if held_size is not None else 0  # the held object itself is not a target
    held = [start.shifted(dz=2.0)] if held_size is not None else []  # a little taller
    regions = []
    for k in range(first, cycles + 1):
        region = start.shifted(dz=-k * step)
        regions.append(region)
        finder.attention(region)
        pos = finder.look(frame, held)
        if pos is not None:
            return SearchResult(True, pos, k, regions, finder.stereo)
    return SearchResult(False, None, cycles, regions)


def snapshot_region(target: Region3D, held_size: Sequence[float] | None = None,
                    margin: float = 5.0) -> Region3D:
    """Where the change-detector looks (Fig. 6(3)): the target, or just above it."""
    if held_size is None:
        return Region3D.around(target.center, target.size + margin)
    c = target.center
    h = float(held_size[2])
    return Region3D.around((c[0], c[1], target.hi[2] + h / 2.0),
                           (held_size[0] + margin, held_size[1] + margin, h))
