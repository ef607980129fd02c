"""Coplanar-detector: are two vertical faces aligned? (Sec. III-D, Fig. 5, used for ALIGN).

Seen from above, two blocks whose named faces are coplanar have one straight
outer edge across both: the line between the blocks meets it in a T-junction.
If the faces are offset the outline has a step, i.e. a pair of L-junctions
(Fig. 5). The detector reads a local window around the two faces in the top
view, extracts each block's outer edge line on that side (the outermost
non-background row or column under each block), back-projects the two edge
lines onto the plane of the edge they show, and calls the faces coplanar when
the step between them is below a tolerance.
"""

from __future__ import annotations

import numpy as np

from .frames import Frame
from .vfd import DARK_MAX, VFD, Region3D

FACES = {"north": (1, +1), "south": (1, -1), "east": (0, +1), "west": (0, -1)}
TOLERANCE_MM = 5.0  # about 1.5 top-view pixels: edges are quantized to whole pixels
MARGIN_MM = 25.0  # how far beyond the faces the local window reaches


class CoplanarDetector(VFD):
    """``check(frame, a, b, face)`` -> coplanar?; ``step_mm`` holds the measured offset."""

    step_mm: float | None = None

    def process(self, frame: Frame) -> None:
        """Coplanarity needs the two boxes: use ``check``."""

    def check(self, frame: Frame, a: Region3D, b: Region3D, face: str) -> bool:
        """Whether face ``face`` (north/south/east/west) of boxes ``a`` and ``b`` is coplanar."""
        if face not in FACES:
            raise ValueError(f"unknown face {face!r}; expected one of {sorted(FACES)}")
        axis, sign = FACES[face]
        lo = np.minimum(a.lo, b.lo) - MARGIN_MM
        hi = np.maximum(a.hi, b.hi) + MARGIN_MM
        lo[2], hi[2] = 0.0, max(a.hi[2], b.hi[2])
        self.attention(Region3D(tuple(lo), tuple(hi)))
        (w,) = self.windows["top"]
        sub = w.read(frame.top) > DARK_MAX
        edges = [self._edge(sub, w, box, axis, sign) for box in (a, b)]
        if None in edges:
            self.step_mm = None
            return False
        self.step_mm = float(edges[0] - edges[1])
        self._target = np.array([(a.center[0] + b.center[0]) / 2, (a.center[1] + b.center[1]) / 2,
                                 max(a.hi[2], b.hi[2])])
        self._found = abs(self.step_mm) <= TOLERANCE_MM
        return self._found

    def _edge(self, mask: np.ndarray, w, box: Region3D, axis: int, sign: int) -> float | None:
        """World coordinate (along ``axis``) of the box's outer edge on the ``sign`` side."""
        cam = self.cameras["top"]
        # The strip of image lines that cross this box only (its middle half across the face).
        other = 1 - axis
        span = box.size[other] / 4.0
        c = box.center
        p0, p1 = c.copy(), c.copy()
        p0[other] -= span
        p1[other] += span
        p0[2] = p1[2] = box.hi[2]
        (u0, v0), (u1, v1) = cam.project(np.array([p0, p1]))
        if axis == 1:  # north/south: the edge is a row; scan the columns of this box
            cols = slice(int(round(min(u0, u1))) - w.x0, int(round(max(u0, u1))) - w.x0 + 1)
            lines = mask[:, cols].T
        else:  # east/west: the edge is a column; scan the rows of this box
            rows = slice(int(round(min(v0, v1))) - w.y0, int(round(max(v0, v1))) + 1 - w.y0)
            lines = mask[rows, :]
        if lines.size == 0 or not lines.any():
            return None
        idx = np.arange(lines.shape[1])
        # +y is up in the top image (smaller rows), +x is right (larger columns).
        outward = (sign > 0) if axis == 0 else (sign < 0)
        hits = [(idx[line].max() if outward else idx[line].min()) for line in lines if line.any()]
        pix = float(np.median(hits)) + (0.5 if outward else -0.5)  # outer pixel boundary
        # The outer silhouette edge is the face's top edge unless the face itself is seen.
        face_pos = box.hi[axis] if sign > 0 else box.lo[axis]
        seen = (cam.center[axis] - face_pos) * sign > 0
        z = box.lo[2] if seen else box.hi[2]
        uv = [0.0, 0.0]
        if axis == 1:
            uv = [(u0 + u1) / 2.0, w.y0 + pix]
        else:
            uv = [w.x0 + pix, (v0 + v1) / 2.0]
        return float(cam.point_on_plane_z(uv, z)[axis])
