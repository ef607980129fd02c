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

import math
from collections.abc import Sequence

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.vision.vfd.base import Region3D, region_mask, silhouette
from perception.vision.vfd.objects_pieces import box_rect
from perception.vision.vfd.resources import Window

VACANT_SHARE = 0.2  # at most this share of the uncovered pixels lit: nothing stands there
MIN_PX = 30  # uncovered pixels needed to decide (a 30 mm leg shows 100-300 at 512 px)
EDGE_PX = 2  # the mask shrunk by this much: a neighbour's edge or a few mm off pose


def uncovered(cam: Camera, center: Sequence[float], size: Sequence[float],
              others: Sequence[tuple[Sequence[float], Sequence[float]]], pad: int = 2
              ) -> tuple[np.ndarray, tuple[int, int, int, int]]:
    """The pixels of a box's projected outline that no box of ``others`` (centre, size)
    covers, as a mask over the image rectangle around it, ``pad`` pixels wider and
    clipped to the image (returned too, as (u0, v0, u1, v1))."""
    lo_u, lo_v, hi_u, hi_v = box_rect(cam, center, size)
    w, h = cam.size
    roi = (min(max(math.floor(lo_u) - pad, 0), w), min(max(math.floor(lo_v) - pad, 0), h),
           min(max(math.ceil(hi_u) + pad + 1, 0), w), min(max(math.ceil(hi_v) + pad + 1, 0), h))
    if roi[2] <= roi[0] or roi[3] <= roi[1]:  # out of the image
        return np.zeros((max(roi[3] - roi[1], 0), max(roi[2] - roi[0], 0)), bool), roi
    window = Window(cam.name, *roi)
    mask = region_mask(cam, Region3D.around(center, size), window)
    for c, s in others:
        mask &= ~region_mask(cam, Region3D.around(c, s), window)
    return mask, roi


def vacant(cam: Camera, img: np.ndarray, center: Sequence[float], size: Sequence[float],
           others: Sequence[tuple[Sequence[float], Sequence[float]]]) -> bool:
    """Whether the view shows the box's spot empty: of its outline, the pixels outside
    every box of ``others`` (one nearer the camera may cover it; one behind it would show
    where it is missing) are at least MIN_PX, and at most VACANT_SHARE of them are lit."""
    mask, roi = uncovered(cam, center, size, others)
    mask = cv2.erode(mask.astype(np.uint8), np.ones((2 * EDGE_PX + 1,) * 2, np.uint8)) > 0
    n = int(mask.sum())
    u0, v0, u1, v1 = roi
    return n >= MIN_PX and float(silhouette(img[v0:v1, u0:u1])[mask].mean()) <= VACANT_SHARE
