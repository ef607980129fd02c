"""Motion-detector: temporal subtraction of subsampled, locally averaged frames (Sec. III-C1).

Each view is read through one whole-image window subsampled every ``step``
pixels (so about 1/16 of the pixels), locally averaged into coarse cells
(footnote 4: a final pixel covers a patch of the input), and stored in a double
buffer at a fixed interval (83.5 ms). The previous buffer is subtracted from the
current one; cells whose change exceeds the threshold are significant, and
their centre of mass in each view is triangulated to a 3-D point, used to
(re)place the hand-tracker.
"""

from __future__ import annotations

from collections.abc import Mapping

import cv2
import numpy as np

from .camera import Camera
from .frames import Frame
from .vfd import VFD, VIEWS
from .vfd_resources import VisionResources

INTERVAL = 0.0835  # s, footnote 4


def _median(a: np.ndarray) -> np.floating:
    """``np.median`` of all elements (same value and dtype), by one partial sort.

    np.median's generic machinery costs ~20 us on the 256 cells; this ~4 us.
    """
    flat = a.ravel()
    k = flat.size // 2
    if flat.size % 2:
        return np.partition(flat, k)[k]
    part = np.partition(flat, (k - 1, k))
    return (part[k - 1] + part[k]) / 2


class MotionDetector(VFD):
    """Finds moving things (the hand) anywhere in the workspace."""

    def __init__(self, cameras: Mapping[str, Camera], resources: VisionResources,
                 interval: float = INTERVAL, step: int = 4, cell: int = 4,
                 threshold: float = 4.0) -> None:
        """Whole-image windows read every ``step`` px, averaged over ``cell`` x ``cell``."""
        super().__init__(cameras, resources)
        self.interval, self.step, self.cell, self.threshold = interval, step, cell, threshold
        try:
            for view in VIEWS:
                w, h = self.cameras[view].size
                self.windows[view].append(resources.allocate(view, (0, 0, w, h), step=step))
        except Exception:
            self.free()  # all or nothing: do not keep half the windows
            raise
        self._buffers: dict[str, np.ndarray] = {}
        self._t_last: float | None = None
        self.image_points: dict[str, tuple[float, float]] = {}
        self.changed_cells = 0

    def reset(self) -> None:
        """Forget the stored buffer and the last detection."""
        super().reset()
        self._buffers = {}
        self._t_last = None
        self.image_points = {}

    def process(self, frame: Frame) -> None:
        """Sample a new buffer every ``interval`` and subtract the previous one."""
        if self._t_last is not None and frame.t - self._t_last < self.interval - 1e-9:
            return
        self._t_last = frame.t
        current: dict[str, np.ndarray] = {}
        for view in VIEWS:
            sub = self.windows[view][0].read(frame.view(view))
            h, w = sub.shape
            current[view] = cv2.resize(sub, (w // self.cell, h // self.cell),
                                       interpolation=cv2.INTER_AREA).astype(np.int16)
        previous, self._buffers = self._buffers, current  # double buffering
        if not previous:
            return
        points = {}
        cells = 0
        for view in VIEWS:
            signed = (current[view] - previous[view]).astype(np.float32)
            diff = np.abs(signed)
            # Most cells see only sensor noise: their robust spread sets the floor, so a
            # noisier camera does not report motion everywhere.
            sigma = 1.4826 * float(_median(np.abs(signed - _median(signed))))
            diff[diff <= max(self.threshold, 5.0 * sigma)] = 0
            ys, xs = np.nonzero(diff)
            if len(xs) == 0:
                return
            cells += len(xs)
            wts = diff[ys, xs]
            total = wts.sum()
            scale = self.step * self.cell  # one coarse cell in input pixels
            points[view] = (float((xs + 0.5) @ wts / total * scale),
                            float((ys + 0.5) @ wts / total * scale))
        self.image_points = points
        self.changed_cells = cells
        self._target = self.triangulate(points["top"], points["side"])
        self._found = True
