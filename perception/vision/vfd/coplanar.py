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

from perception.vision.frames import Frame
from perception.vision.vfd.base import DARK_MAX, HAND_BAND, VFD, Region3D

FACES = {"north": (1, +1), "south": (1, -1), "east": (0, +1), "west": (0, -1)}
TOLERANCE_MM = 5.0  # about 1.5 top-view pixels: edges are quantized to whole pixels
MARGIN_MM = 25.0  # how far beyond the faces the local window reaches
HAND_PIXELS = 2  # this many hand-band pixels on a face's scan lines: the hand is over it
REACH_MM = 15.0  # a free face's outline must end within this distance past the model face


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
        raw = w.read(frame.top)
        sub = raw > DARK_MAX
        # The hand (palm and fingers are in the hand band) on a scan line makes the outline
        # its own there: that face is not measurable while the hand is over it.
        hand = (raw >= HAND_BAND[0]) & (raw < HAND_BAND[1])
        edges = [self._edge(sub, w, box, axis, sign, hand) for box in (a, b)]
        if None in edges:
            self.step_mm = None
            return False
        self.step_mm = float(edges[0] - edges[1])
        self._target = np.array([(a.center[0] + b.center[0]) / 2, (a.center[1] + b.center[1]) / 2,
                                 max(a.hi[2], b.hi[2])])
        self._found = abs(self.step_mm) <= TOLERANCE_MM
        return self._found

    def coplanar_faces(self, frame: Frame, a: Region3D, b: Region3D) -> list[str]:
        """The faces (of north/south/east/west) that ``a`` and ``b`` have coplanar."""
        return [face for face in FACES if self.check(frame, a, b, face)]

    def _edge(self, mask: np.ndarray, w, box: Region3D, axis: int, sign: int,
              hand: np.ndarray | None = None) -> float | None:
        """World coordinate (along ``axis``) of the box's free outer edge on the ``sign`` side.

        Each scan line runs from the box centre outwards; the edge is where the
        silhouette first ends. If it does not end within REACH_MM past the face,
        something touches that face and the face cannot be measured (None).
        """
        cam = self.cameras["top"]
        other = 1 - axis
        c = box.center.copy()
        c[2] = box.hi[2]
        span = box.size[other] / 4.0  # the middle half of the face: clear of corners
        ends = []
        for off in (-span, span):
            p = c.copy()
            p[other] += off
            q = p.copy()
            q[axis] = (box.hi[axis] if sign > 0 else box.lo[axis]) + sign * REACH_MM
            ends.append(cam.project(np.array([p, q])))
        (p0, q0), (p1, q1) = ends
        # Image axis of the scan: x for east/west, y for north/south (top view).
        k = 0 if axis == 0 else 1
        start = int(round((p0[k] + p1[k]) / 2.0)) - (w.x0 if k == 0 else w.y0)
        stop = int(round((q0[k] + q1[k]) / 2.0)) - (w.x0 if k == 0 else w.y0)
        step = 1 if stop > start else -1
        across = sorted([p0[1 - k], p1[1 - k]])
        lo_line = int(round(across[0])) - (w.y0 if k == 0 else w.x0)
        hi_line = int(round(across[1])) - (w.y0 if k == 0 else w.x0)
        lines = mask[lo_line:hi_line + 1, :] if k == 0 else mask[:, lo_line:hi_line + 1].T
        if hand is not None:
            near = hand[lo_line:hi_line + 1, :] if k == 0 else hand[:, lo_line:hi_line + 1].T
            a, b = sorted((start, stop))
            if np.count_nonzero(near[:, max(0, a):b + 1]) >= HAND_PIXELS:
                return None
        hits = []
        for line in lines:
            run = line[start:stop + step:step] if stop + step >= 0 else line[start::step]
            gaps = np.nonzero(~run)[0]
            if len(gaps) == 0 or gaps[0] == 0:
                continue
            hits.append(start + step * (gaps[0] - 1))
        if len(hits) < max(1, len(lines) // 2):
            return None
        pix = float(np.median(hits)) + 0.5 * step  # outer boundary (pixel centres at integers)
        face_pos = box.hi[axis] if sign > 0 else box.lo[axis]
        seen = (cam.center[axis] - face_pos) * sign > 0
        z = box.lo[2] if seen else box.hi[2]  # the outline is the face's bottom edge if seen
        if k == 0:
            uv = [w.x0 + pix, (p0[1] + p1[1]) / 2.0]
        else:
            uv = [(p0[0] + p1[0]) / 2.0, w.y0 + pix]
        return float(cam.point_on_plane_z(uv, z)[axis])
