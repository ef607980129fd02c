"""Who the detectors watch: a subject's appearance in the images (issue #13, Sec. IX-C2).

The hand-tracker, the change- and coplanar-detectors and the block silhouette
find the watched subject by its gray band (``base.HAND_BAND``: the
demonstrator's hand, drawn flat at 128). The paper proposes to watch the
robot with the same recognizer; the robot's gripper is drawn flat at 80
(docs/vision.md). Rather than give every detector a second band, the camera
side maps the subject's own band onto the band the detectors key on, pixel by
pixel (one lookup table per subject; a colour calibration, not a read of the
world). The detectors then run unchanged on the robot's frames.

| subject   | drawn at | band read as the subject | why the band's ends                          |
|-----------|----------|--------------------------|----------------------------------------------|
| hand      | 128      | 104..150 (HAND_BAND)     | blocks are >= 170, the arm 80                |
| gripper   | 80       | 68..96                   | crease lines are 60, the hand band from 104; |
|           |          |                          | 68 is 4 sigma of the default noise above 60  |
"""

from __future__ import annotations

import cv2
import numpy as np

from perception.vision.frames import Frame
from perception.vision.vfd.base import HAND_BAND

SUBJECT_BANDS: dict[str, tuple[int, int]] = {"hand": HAND_BAND, "gripper": (68, 96)}
SEEN_GRAY = (HAND_BAND[0] + HAND_BAND[1]) // 2  # where a mapped subject pixel lands (127)


def subject_table(subject: str) -> np.ndarray:
    """The 256-entry lookup table that shows ``subject``'s band as the hand band."""
    if subject not in SUBJECT_BANDS:
        raise KeyError(f"no subject called {subject!r}; known: {sorted(SUBJECT_BANDS)}")
    table = np.arange(256, dtype=np.uint8)
    if SUBJECT_BANDS[subject] != HAND_BAND:
        lo, hi = SUBJECT_BANDS[subject]
        table[lo:hi + 1] = SEEN_GRAY
    return table


def as_subject(frame: Frame, table: np.ndarray) -> Frame:
    """``frame`` with its subject's pixels moved into the band the detectors read."""
    return Frame(frame.index, frame.t, cv2.LUT(frame.top, table), cv2.LUT(frame.side, table))
