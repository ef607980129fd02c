"""Is the block the robot believes it carries still between its jaws? (issue #13, drops)

A drop lets the block fall halfway through a transfer; when it lands on its goal
anyway, the state the monitor measures afterwards is the plan's, and the robot watch
recognizes the usual place (helper round 22: two of six drops). What tells is the
carry itself: while the jaws, by the robot's own sense, are closed on a block, the
space just above the fingertips between them is filled by that block (the grasp keeps
the fingertips a millimetre above the block's bottom, ``commands.yaml`` gripper.tip).
The robot knows where its jaws are and how wide they stand; the views show whether
that space is lit (a block) or dark. Pixels its own fingers and palm may cover are
left out; a view with too few pixels left decides nothing.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from perception.vision.camera import Camera
from perception.vision.vfd.base import silhouette
from perception.vision.vfd.objects_back import uncovered

BAND_MM = (2.0, 8.0)  # the space above the fingertips that a held block fills, mm
SHARE = 0.6  # of the jaws' opening (and of FINGER_MM across): inside the block's faces
FINGER_MM = 20.0  # the fingers' depth across the jaws: a held block is at least that wide
MIN_PX = 6  # pixels needed in a view to decide
EMPTY_SHARE = 0.2  # at most this share lit: nothing between the jaws


def jaw_space(grip: Sequence[float], axis: int, opening: float, tip: float
              ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Centre and size of the box between the jaws, just above the fingertips."""
    along = SHARE * opening
    across = SHARE * min(opening, FINGER_MM)
    lo, hi = BAND_MM
    z = float(grip[2]) - tip + (lo + hi) / 2.0
    size = (along, across, hi - lo) if axis == 0 else (across, along, hi - lo)
    return (float(grip[0]), float(grip[1]), z), size


def jaws_empty(cameras: Mapping[str, Camera], images: Mapping[str, np.ndarray],
               space: tuple[Sequence[float], Sequence[float]],
               own: Sequence[tuple[Sequence[float], Sequence[float]]]) -> bool | None:
    """True when every view that shows enough of ``space`` (its outline less the boxes
    ``own``: the robot's fingers and palm) shows it dark; None when none shows enough."""
    said = []
    for name, img in images.items():
        mask, roi = uncovered(cameras[name], *space, own)
        if int(mask.sum()) >= MIN_PX:
            u0, v0, u1, v1 = roi
            lit = silhouette(img[v0:v1, u0:u1])[mask]
            said.append(float(lit.mean()) <= EMPTY_SHARE)
    return all(said) if said else None
