"""Who the detectors watch: a subject's appearance in the images (issue #13, Sec. IX-C2).

The hand-tracker, the change- and coplanar-detectors and the block silhouette
find the watched subject by its gray band (``base.HAND_BAND``: the
demonstrator's hand, drawn flat at 128). The paper proposes to watch the
robot with the same recognizer; the robot's gripper is drawn flat at 80
(docs/vision.md). Rather than give every detector a second band, the camera
side maps the subject's own band onto the band the detectors key on (a colour
calibration on the images, not a read of the world; ``SubjectView``). The
detectors then run unchanged on the robot's frames.

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


class SubjectView:
    """Shows ``subject``'s pixels in the band the detectors read as the watched subject.

    The hand's own band is left as it is. Another subject's band is narrower (the crease
    lines of 1 px at 60 lie close below the gripper's 80; with strong noise some crease
    pixels fall into its band and some of the gripper's out of it), so its mask is opened
    with a 2 x 2 square, which removes 1-px lines and lone pixels while the gripper's
    parts (fingers about 3 px wide) stay, then closed with a 3 x 3 square, which takes
    back its pixels that noise pushed out of the band.
    """

    def __init__(self, subject: str) -> None:
        """Prepare the masks' kernels; KeyError for an unknown subject."""
        if subject not in SUBJECT_BANDS:
            raise KeyError(f"no subject called {subject!r}; known: {sorted(SUBJECT_BANDS)}")
        self.band = SUBJECT_BANDS[subject]
        self.same = self.band == HAND_BAND
        self.open_k = np.ones((2, 2), np.uint8)
        self.close_k = np.ones((3, 3), np.uint8)

    def image(self, img: np.ndarray) -> np.ndarray:
        """One view with the subject's pixels set to SEEN_GRAY."""
        if self.same:
            return img
        mask = cv2.inRange(img, self.band[0], self.band[1])
        mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, self.open_k)
        mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, self.close_k)
        out = img.copy()
        out[mask > 0] = SEEN_GRAY
        return out

    def frame(self, frame: Frame) -> Frame:
        """``frame`` with its subject's pixels moved into the band the detectors read."""
        return Frame(frame.index, frame.t, self.image(frame.top), self.image(frame.side))
