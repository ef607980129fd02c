"""Columns under a top face, read in the side view: the object-finder's height fallback.

When a top face is too thin to see from the side, or hidden there, its height is
the h whose box [footprint at h] x [0, h] best explains the side view's silhouettes
(Sec. III-B's correspondence, from the other end). ``Columns`` draws such boxes
into the side image and measures them; ``ObjectFinder`` (objects.py) asks it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import cv2
import numpy as np

from perception.vision.camera import Camera

# A column read by its top edge (solid up to h, dark just above) must show a block at that
# edge: its top COLUMN_TOP_MM solid over at least COLUMN_SOLID of their side image. Above a
# thin pillar everything is dark, and a column 80 mm too tall outscored the pillar's own
# height (bench 1267). Only the top is asked: lower down, a block standing on something
# narrower overhangs background (a cube pushed to a plank's edge, fault bench 3001).
COLUMN_SOLID, COLUMN_TOP_MM = 0.8, 15.0
# A block on the table behind others, read from above alone (``Columns.behind``): its face
# at the shape's own height is that shape's footprint within FIT_MM a side, and its whole
# column falls on blocks in front in the side view (HIDDEN of its image solid: its hull,
# drawn a pixel wide, may graze the background at its edges).
FIT_MM, HIDDEN = 4.0, 0.9
HIDDEN_SHARE = 0.5  # at most this share of such a face may lie under the block in front
STACK_SUM_MM = 2.0  # a silhouette this near the height of a stack of shapes may be one

Footprint = Callable[[tuple, float], tuple[float, float, float, float]]


class Columns:
    """Side-view boxes [footprint of a top-view face at h] x [z0, h]."""

    def __init__(self, cameras: Mapping[str, Camera], footprint: Footprint) -> None:
        """``footprint(rect, h)``: a top-view face's world extents lifted to height h."""
        self.cameras, self.footprint = cameras, footprint

    def height(self, rect, blobs: np.ndarray, areas: np.ndarray, solid: np.ndarray,
               rim: bool = False) -> tuple[float, float]:
        """Height whose box [footprint] x [0, h] best explains the side view.

        Either the column covers one side-view silhouette (IoU), or, where the
        silhouette runs on into a block in front of the column (a 10 mm cube behind a
        plate's edge is one blob with it), the column is solid up to h (its top
        COLUMN_TOP_MM at least COLUMN_SOLID) and the side image is dark just above it
        (its top edge). A ``rim`` (a face framing another) is exempt: its column up
        to the top of the block standing in it is hollow beside that block, and that
        height is what makes it a rim (``objects_rings.find_rims``; bench 1068, a disc
        under a brick).
        """

        def score(h: float) -> float:
            """The better of the two fits at height ``h``."""
            hull = self.hull(rect, h, blobs.shape)
            if hull is None:
                return 0.0
            (ox, oy), mask = hull
            under = blobs[oy:oy + mask.shape[0], ox:ox + mask.shape[1]][mask > 0]
            counts = np.bincount(under, minlength=2)
            counts[0] = 0
            best = int(counts.argmax())
            iou = counts[best] / float(len(under) + areas[best] - counts[best])
            top = self.solid_fraction(rect, h, solid, max(0.0, h - COLUMN_TOP_MM))
            if top < COLUMN_SOLID and not rim:
                return float(iou)
            return max(iou, self.solid_fraction(rect, h, solid) * self.dark_above(
                rect, h, solid))

        coarse = [(score(h), h) for h in np.arange(1.0, 300.0, 2.0)]
        best, h0 = max(coarse)
        fine = [(score(h), h) for h in np.arange(h0 - 2.0, h0 + 2.01, 0.25)]
        top_score = max(fine)[0]
        hits = [h for sc, h in fine if sc >= top_score - 1e-9]
        return float(np.mean(hits)), max(best, top_score)

    def hull(self, rect, h: float, shape, z0: float = 0.0
             ) -> tuple[tuple[int, int], np.ndarray] | None:
        """Side-view mask (origin, mask) of the box [footprint at h] x [z0, h], if in view."""
        x0, y0, x1, y1 = self.footprint(rect, h)
        corners = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, h)])
        uv = self.cameras["side"].project(corners)
        ox, oy = np.floor(uv.min(axis=0)).astype(int)
        ex, ey = np.ceil(uv.max(axis=0)).astype(int) + 1
        if ox < 0 or oy < 0 or ex > shape[1] or ey > shape[0]:
            return None
        hull = cv2.convexHull(np.rint((uv - (ox, oy)) * 16).astype(np.int32))
        mask = np.zeros((ey - oy, ex - ox), np.uint8)
        cv2.fillConvexPoly(mask, hull, 1, cv2.LINE_8, 4)
        return (ox, oy), mask

    def dark_above(self, rect, h: float, solid: np.ndarray) -> float:
        """Dark fraction of the side-view band a column as tall as ``h`` + 2 px would add."""
        grown = h + 2.0 / self.cameras["side"].mm_to_px((0.0, 200.0, h))
        hulls = [self.hull(rect, z, solid.shape) for z in (h, grown)]
        if None in hulls:
            return 0.0
        x0 = min(o[0] for o, _ in hulls)
        y0 = min(o[1] for o, _ in hulls)
        x1 = max(o[0] + m.shape[1] for o, m in hulls)
        y1 = max(o[1] + m.shape[0] for o, m in hulls)
        canvas = []
        for (ox, oy), m in hulls:
            c = np.zeros((y1 - y0, x1 - x0), bool)
            c[oy - y0:oy - y0 + m.shape[0], ox - x0:ox - x0 + m.shape[1]] = m > 0
            canvas.append(c)
        band = canvas[1] & ~canvas[0]
        n = int(band.sum())
        if n == 0:
            return 0.0
        return 1.0 - float(solid[y0:y1, x0:x1][band].sum()) / n

    def behind(self, rect, solid: np.ndarray, shapes: Mapping[str, tuple],
               others: list) -> tuple[float, tuple] | None:
        """A block standing on the table that the side view cannot see at all (the blocks
        in front hide it), read from the top view alone: (height, face rect). Its height
        is the one shape height at which the face's footprint is that shape's; where a
        face in ``others`` abuts it, the face may be short of the shape on that side (a
        higher block in front hides a band of it from above), and the rect returned
        reaches under that face. None when no height, or more than one, fits, or when
        the column would show in the side view. A cube knocked off a plank onto the
        table behind the plank's pillar showed only its top (fault bench 3001)."""
        fits = set()  # (height, face): shapes of one height and size read alike
        for sx, sy, sz in shapes.values():
            for size in ((sx, sy), (sy, sx)):
                whole = _completed(rect, self.footprint(rect, float(sz)), size, others)
                if whole is not None:
                    fits.add((float(sz), tuple(round(float(v), 1) for v in whole)))
        if len(fits) != 1:
            return None  # no shape, or several that read the face differently
        (h, whole), = fits
        return (h, whole) if self.solid_fraction(whole, h, solid) >= HIDDEN else None

    def stacked(self, rect, h: float, shapes: Mapping[str, tuple]) -> bool:
        """Whether a column ``h`` high under this face could be two or three blocks: a
        shape whose footprint the face is at ``h`` on one or two others, their heights
        summing to ``h`` within STACK_SUM_MM."""
        extent = self.footprint(rect, h)
        tops = [s[2] for s in shapes.values() if any(  # the face is its footprint as seen
            _completed(rect, extent, size, []) is not None
            for size in ((s[0], s[1]), (s[1], s[0])))]
        zs = [s[2] for s in shapes.values()]
        return any(abs(t + u - h) <= STACK_SUM_MM or any(abs(t + u + v - h) <= STACK_SUM_MM
                                                         for v in zs)
                   for t in tops for u in zs)

    def solid_fraction(self, rect, h: float, solid: np.ndarray, z0: float = 0.0) -> float:
        """Fraction of the side-view image of the column [footprint] x [z0, h] not dark."""
        hull = self.hull(rect, h, solid.shape, z0)
        if hull is None:
            return 0.0
        (ox, oy), mask = hull
        inside = mask > 0
        n = int(inside.sum())
        return float(solid[oy:oy + mask.shape[0], ox:ox + mask.shape[1]][inside].sum()) / n \
            if n else 0.0

    def candidates(self, rect, labels: np.ndarray, areas: np.ndarray, solid: np.ndarray,
                   min_score: float, keep: int) -> list[tuple[float, float, int]]:
        """Candidate heights of a top face: (score, h, side face label), best few first.

        Lifted to the right height h, the face's footprint projects onto one
        side-view top-face region and covers it (high intersection over union);
        lifted elsewhere it falls on a front face, on the background, on a part
        of some larger face, or on the top face of a block in front of it. The
        column under the footprint down to the table must also look solid in
        the side view (the face is supported).
        """
        cam = self.cameras["side"]

        def ious(h: float) -> np.ndarray | None:
            """IoU of the lifted footprint with every side top face, times the solid part."""
            x0, y0, x1, y1 = self.footprint(rect, h)
            quad = np.array([[x0, y0, h], [x1, y0, h], [x1, y1, h], [x0, y1, h]])
            uv = cam.project(quad)
            ox, oy = np.floor(uv.min(axis=0)).astype(int) - 1
            ex, ey = np.ceil(uv.max(axis=0)).astype(int) + 2
            if ox < 0 or oy < 0 or ex > labels.shape[1] or ey > labels.shape[0]:
                return None
            mask = np.zeros((ey - oy, ex - ox), np.uint8)
            cv2.fillConvexPoly(mask, np.rint((uv - (ox, oy)) * 16).astype(np.int32), 1,
                               cv2.LINE_8, 4)
            under = labels[oy:ey, ox:ex][mask > 0]
            counts = np.bincount(under, minlength=len(areas)).astype(float)
            counts[0] = 0.0
            if not counts.any():
                return None
            iou = counts / (len(under) + areas - counts)
            return iou * self.solid_fraction(rect, h, solid)

        best: dict[int, tuple[float, float]] = {}  # label -> (score, h) on the coarse grid
        for h in np.arange(1.0, 300.0, 2.0):
            sc = ious(h)
            if sc is None:
                continue
            for lab in np.flatnonzero(sc >= min_score):
                if sc[lab] > best.get(lab, (0.0, 0.0))[0]:
                    best[int(lab)] = (float(sc[lab]), float(h))
        out = []
        for lab, (sc0, h0) in sorted(best.items(), key=lambda kv: -kv[1][0])[:keep]:
            fine = []
            for h in np.arange(h0 - 2.0, h0 + 2.01, 0.25):
                sc = ious(h)
                fine.append((float(sc[lab]) if sc is not None else 0.0, float(h)))
            top = max(fine)[0]
            hits = [h for s, h in fine if s >= top - 1e-9]
            out.append((max(sc0, top), float(np.mean(hits)), lab))
        return sorted(out, reverse=True)


def _completed(rect, extent, size, others) -> tuple | None:
    """``rect`` (x0, y0, x1, y1 px) grown to a face of ``size`` (mm) whose ``extent`` (its
    world footprint) it shows, or None: along each axis the face is as long as the size
    within FIT_MM, or shorter and abutted on one side by a face in ``others``."""
    out = list(rect)
    for a, world in ((0, extent[2] - extent[0]), (1, extent[3] - extent[1])):
        short = size[a] - world
        if abs(short) <= FIT_MM:
            continue
        if short < 0 or short > HIDDEN_SHARE * size[a]:
            return None  # longer than the shape, or mostly unseen: a rim, not a top
        b = 1 - a
        beside = [o for o in others if min(o[2 + b], rect[2 + b]) > max(o[b], rect[b])]
        px = short * (rect[2 + a] - rect[a]) / world  # image px per mm along this axis
        if any(abs(o[a] - rect[2 + a]) <= 1.0 for o in beside):
            out[2 + a] += px  # the face abutting it is past its far edge
        elif any(abs(o[2 + a] - rect[a]) <= 1.0 for o in beside):
            out[a] -= px
        else:
            return None
    return tuple(out)
