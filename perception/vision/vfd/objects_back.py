"""Is a hidden block there? The execution workspace's third view answers (issue #13).

The monitor's looks measure the workspace from the top and side views
(``objects_posed.explain``), which accept a block that neither view shows at the
pose the plan expects, as long as something covers it: a table's back leg under its
top and behind its front leg, a pyramid's middle cube under the next level and
behind the front cube. Taken away, such a block was never missed (helper round 22:
a leg removed, the cameras' verdict true, the simulator's false). A third camera
(``camera.back_camera``, from behind the far corner) is asked, for such a block,
whether the part of its expected box's outline that no other block's outline meets
is dark: then its spot is empty. Too few such pixels decides nothing.
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.vision.vfd.base import silhouette

VACANT_SHARE = 0.2  # at most this share of the uncovered pixels lit: nothing stands there
MIN_PX = 30  # uncovered pixels needed to decide (a 30 mm leg shows 100-300 at 512 px)
EDGE_PX = 2  # the mask shrunk by this much: a neighbour's edge or a few mm off pose


def box_mask(cam: Camera, center: Sequence[float], size: Sequence[float],
             roi: tuple[int, int, int, int] | None = None) -> np.ndarray:
    """The pixels of an axis-aligned box's projected outline, boolean, over the whole
    image or over ``roi`` = (u0, v0, u1, v1) only."""
    c, h = np.asarray(center, float), np.asarray(size, float) / 2.0
    corners = np.array([c + h * (sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1)
                        for sz in (-1, 1)])
    u0, v0, u1, v1 = roi if roi is not None else (0, 0, cam.size[0], cam.size[1])
    if u1 <= u0 or v1 <= v0:  # out of the image
        return np.zeros((max(v1 - v0, 0), max(u1 - u0, 0)), bool)
    uv = cam.project(corners) - (u0, v0)
    hull = cv2.convexHull(np.rint(uv * 16).astype(np.int32))
    mask = np.zeros((v1 - v0, u1 - u0), np.uint8)
    cv2.fillConvexPoly(mask, hull, 1, cv2.LINE_8, 4)
    return mask > 0


def box_roi(cam: Camera, center: Sequence[float], size: Sequence[float], pad: int = 2
            ) -> tuple[int, int, int, int]:
    """The image rectangle around a box's projection, ``pad`` pixels wider, in the image."""
    c, h = np.asarray(center, float), np.asarray(size, float) / 2.0
    uv = cam.project(np.array([c + h * (sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1)
                               for sz in (-1, 1)]))
    lo, hi = np.floor(uv.min(axis=0)) - pad, np.ceil(uv.max(axis=0)) + pad + 1
    w, hgt = cam.size
    return (int(min(max(lo[0], 0), w)), int(min(max(lo[1], 0), hgt)),
            int(min(max(hi[0], 0), w)), int(min(max(hi[1], 0), hgt)))


def vacant(cam: Camera, img: np.ndarray, center: Sequence[float], size: Sequence[float],
           others: Sequence[tuple[Sequence[float], Sequence[float]]]) -> bool:
    """Whether the view shows the box's spot empty: of its outline, the pixels outside
    every box of ``others`` (one nearer the camera may cover it; one behind it would show
    where it is missing) are at least MIN_PX, and at most VACANT_SHARE of them are lit."""
    roi = box_roi(cam, center, size)
    mask = box_mask(cam, center, size, roi)
    if not mask.any():
        return False
    for c, s in others:
        mask &= ~box_mask(cam, c, s, roi)
    mask = cv2.erode(mask.astype(np.uint8), np.ones((2 * EDGE_PX + 1,) * 2, np.uint8)) > 0
    n = int(mask.sum())
    u0, v0, u1, v1 = roi
    return n >= MIN_PX and float(silhouette(img[v0:v1, u0:u1])[mask].mean()) <= VACANT_SHARE
