"""Object-finder: the initial state from the two views (Sec. III-B).

Coarse to fine: a subsampled top view finds the block silhouettes; a
full-resolution window on each one segments its top faces (the brightest
shade; crease lines split stacked faces). Each top face is put in
correspondence with the side view by a height search: the face's footprint,
back-projected from the top view onto a plane of height h, must land on
top-face pixels when projected into the side view. That height, the footprint's
extent and the top face found under it (or the table) give the box; its shape
name is the nearest size in the shape database.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from .frames import Frame
from .vfd import DARK_MAX, VFD

TOP_MIN = 240  # block top faces are drawn at 255, the other faces at most 205
COARSE = 4  # subsampling of the first, coarse look
MIN_FACE_PX = 6


@dataclass(frozen=True)
class FoundObject:
    """A block recognized in the initial state."""

    shape: str
    position: tuple[float, float, float]  # box centre, mm
    size: tuple[float, float, float]  # measured extents, mm
    mismatch: float  # mm, summed |measured - database size|


class ObjectFinder(VFD):
    """``find(frame, shapes)`` -> list of FoundObject (the :Loc-exist detector, Table III)."""

    def process(self, frame: Frame) -> None:
        """The object-finder runs once on request: use ``find``."""

    def find(self, frame: Frame, shapes: Mapping[str, Sequence[float]]) -> list[FoundObject]:
        """Segment, correspond, measure and name every block visible in ``frame``."""
        faces = self._top_faces(frame.top)
        (w, h) = self.cameras["side"].size
        side_win = self.resources.allocate("side", (0, 0, w, h))
        try:
            side = side_win.read(frame.side) >= TOP_MIN
        finally:
            self.resources.free(side_win)
        boxes = []
        for rect, pts in faces:
            height, score = self._height(pts, side)
            if score < 0.3:
                continue
            boxes.append((height, self._footprint(rect, height)))
        found = []
        for height, (x0, y0, x1, y1) in boxes:
            cx, cy = (x0 + x1) / 2.0, (y0 + y1) / 2.0
            below = [h for h, (a0, b0, a1, b1) in boxes
                     if h < height - 3.0 and a0 <= cx <= a1 and b0 <= cy <= b1]
            base = max(below, default=0.0)
            size = np.array([x1 - x0, y1 - y0, height - base])
            name, mismatch = _nearest(shapes, size)
            found.append(FoundObject(name, (cx, cy, base + size[2] / 2.0),
                                     tuple(size.tolist()), mismatch))
        self._found = bool(found)
        self._target = np.array([f.position for f in found]) if found else None
        return found

    def _top_faces(self, top: np.ndarray) -> list[tuple[tuple, np.ndarray]]:
        """Top faces in the top view: pixel rectangle (x0, y0, x1, y1) and pixel centres."""
        w, h = self.cameras["top"].size
        coarse_win = self.resources.allocate("top", (0, 0, w, h), step=COARSE)
        try:
            coarse = (coarse_win.read(top) > DARK_MAX).astype(np.uint8)
        finally:
            self.resources.free(coarse_win)
        n, _, stats, _ = cv2.connectedComponentsWithStats(coarse, connectivity=8)
        rects = []
        for i in range(1, n):
            x, y, bw, bh = stats[i, :4]
            rect = (max(0, (x - 1) * COARSE), max(0, (y - 1) * COARSE),
                    min(w, (x + bw + 1) * COARSE), min(h, (y + bh + 1) * COARSE))
            fine = self.resources.allocate("top", rect)
            try:
                face = (fine.read(top) >= TOP_MIN).astype(np.uint8)
            finally:
                self.resources.free(fine)
            m, labels, fst, _ = cv2.connectedComponentsWithStats(face, connectivity=4)
            for j in range(1, m):
                fx, fy, fw, fh, area = fst[j]
                if area >= MIN_FACE_PX:
                    # The crease line drawn on the face outline hides half a pixel per side.
                    rect = (fine.x0 + fx - 0.5, fine.y0 + fy - 0.5,
                            fine.x0 + fx + fw + 0.5, fine.y0 + fy + fh + 0.5)
                    ys, xs = np.nonzero(labels == j)
                    pick = slice(None, None, max(1, len(xs) // 400))
                    pts = np.stack([xs[pick] + fine.x0 + 0.5, ys[pick] + fine.y0 + 0.5], axis=1)
                    rects.append((rect, pts))
        return rects

    def _footprint(self, rect, height: float) -> tuple[float, float, float, float]:
        """World extents (x0, y0, x1, y1) of a top-face pixel rectangle at ``height``."""
        cam = self.cameras["top"]
        pts = np.array([cam.point_on_plane_z((u, v), height)[:2]
                         for u in (rect[0], rect[2]) for v in (rect[1], rect[3])])
        return (float(pts[:, 0].min()), float(pts[:, 1].min()),
                float(pts[:, 0].max()), float(pts[:, 1].max()))

    def _height(self, pts: np.ndarray, side: np.ndarray) -> tuple[float, float]:
        """Height of a top face: where its pixels, lifted to height h, hit side top faces."""
        top, cam = self.cameras["top"], self.cameras["side"]
        dirs = (top._M_inv @ np.column_stack([pts, np.ones(len(pts))]).T).T  # view lines
        o = top.center
        hgt, wid = side.shape

        def score(h: float) -> float:
            world = o + dirs * ((h - o[2]) / dirs[:, 2])[:, None]
            uv = np.floor(cam.project(world)).astype(int)
            ok = (uv[:, 0] >= 0) & (uv[:, 0] < wid) & (uv[:, 1] >= 0) & (uv[:, 1] < hgt)
            return float(side[uv[ok, 1], uv[ok, 0]].sum()) / len(pts)

        coarse = [(score(h), h) for h in np.arange(1.0, 300.0, 2.0)]
        best, h0 = max(coarse)
        fine = [(score(h), h) for h in np.arange(h0 - 2.0, h0 + 2.01, 0.25)]
        top_score = max(fine)[0]
        hits = [h for s, h in fine if s >= top_score - 1e-9]
        return float(np.mean(hits)), max(best, top_score)


def _nearest(shapes: Mapping[str, Sequence[float]], size: np.ndarray) -> tuple[str, float]:
    """The database shape whose size is closest to ``size`` (summed absolute error)."""
    if not shapes:
        return "unknown", float("inf")
    errs = {name: float(np.abs(np.asarray(s, float) - size).sum()) for name, s in shapes.items()}
    name = min(errs, key=errs.get)
    return name, errs[name]
