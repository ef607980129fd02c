"""Motion-detector: temporal subtraction of subsampled, locally averaged frames (Sec. III-C1).

Each view is read through one whole-image window subsampled every ``step``
pixels (so about 1/16 of the pixels), locally averaged into coarse cells
(footnote 4: a final pixel covers a patch of the input), and stored in a double
buffer at a fixed interval (83.5 ms). The previous buffer is subtracted from the
current one; cells whose change exceeds the threshold are significant, and
their centre of mass in each view is triangulated to a 3-D point, used to
(re)place the hand-tracker.

Noise: the significance floor is 5 x the robust spread of all cell changes,
but cells are whole gray levels, so that spread cannot go below one level and
the floor stops growing with the sensor noise (the same 7.4 at std 4 and 8).
At high noise a lone cell then passes it in a view where the hand barely
changes the image (a slow descent seen from above), and the triangulated point
lands far from the hand. So each view must also hold one seed cell above
SEED_K x the sensor noise of a cell change, measured from the sampled pixels
that are neither black nor saturated (a running median, refreshed every few
buffers); weaker significant cells only refine the centre, and only within
two cells of a seed (a lone noise cell elsewhere would pull it off the hand).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.vision.frames import Frame
from perception.vision.vfd.base import DARK_MAX, VFD, VIEWS
from perception.vision.vfd.resources import VisionResources

INTERVAL = 0.0835  # s, footnote 4
SEED_K = 4.0  # a view moves only if one cell changes by more than this x the cell noise
NOISE_EVERY = 4  # measure the sensor noise on every 4th buffer pair (~3 times a second)
NOISE_HISTORY = 16  # running median over the last measurements
NOISE_MIN_PIXELS = 32  # fewer unclipped pixels than this: no measurement
_NEAR = np.ones((5, 5), np.uint8)  # a weak cell refines the centre within 2 cells of a seed


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
        self._samples: dict[str, np.ndarray] = {}  # the sampled pixels behind the buffers
        self._t_last: float | None = None
        self._pairs = 0  # buffer pairs compared so far
        self._noise: deque[float] = deque(maxlen=NOISE_HISTORY)  # median |pixel change|
        self.sensor_noise = 0.0  # std of a sampled pixel's change between buffers
        self.image_points: dict[str, tuple[float, float]] = {}
        self.changed_cells = 0

    def reset(self) -> None:
        """Forget the stored buffer and the last detection."""
        super().reset()
        self._buffers = {}
        self._samples = {}
        self._t_last = None
        self.image_points = {}

    def process(self, frame: Frame) -> None:
        """Sample a new buffer every ``interval`` and subtract the previous one."""
        if self._t_last is not None and frame.t - self._t_last < self.interval - 1e-9:
            return
        self._t_last = frame.t
        current: dict[str, np.ndarray] = {}
        samples: dict[str, np.ndarray] = {}
        for view in VIEWS:
            samples[view] = sub = self.windows[view][0].read(frame.view(view))
            h, w = sub.shape
            current[view] = cv2.resize(sub, (w // self.cell, h // self.cell),
                                       interpolation=cv2.INTER_AREA).astype(np.int16)
        previous, self._buffers = self._buffers, current  # double buffering
        before, self._samples = self._samples, samples
        if not previous:
            return
        if self._pairs % NOISE_EVERY == 0:
            self._measure_noise(before, samples)
        self._pairs += 1
        # A cell averages cell x cell samples: its change is that much less noisy.
        seed = SEED_K * self.sensor_noise / self.cell
        points = {}
        cells = 0
        for view in VIEWS:
            signed = (current[view] - previous[view]).astype(np.float32)
            diff = np.abs(signed)
            # Most cells see only sensor noise: their robust spread sets the floor, so a
            # noisier camera does not report motion everywhere.
            sigma = 1.4826 * float(_median(np.abs(signed - _median(signed))))
            floor = max(self.threshold, 5.0 * sigma)
            diff[diff <= floor] = 0
            if float(diff.max()) <= seed:
                return  # nothing, or only changes the sensor noise can make
            if seed > floor:  # weak cells count only next to a seed (hysteresis)
                near = cv2.dilate((diff > seed).view(np.uint8), _NEAR)
                diff[near == 0] = 0
            ys, xs = np.nonzero(diff)
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

    def _measure_noise(self, before: Mapping[str, np.ndarray],
                       now: Mapping[str, np.ndarray]) -> None:
        """Update ``sensor_noise`` from the sampled pixels that are neither black nor
        saturated in both buffers (there the noise is not clipped): 1.4826 x the median
        absolute change, a moving hand's pixels being a minority."""
        changes = []
        for view in VIEWS:
            a, b = before[view], now[view]
            lo, hi = np.minimum(a, b), np.maximum(a, b)
            keep = (lo > DARK_MAX) & (hi < 255 - DARK_MAX)
            changes.append(np.abs(b[keep].astype(np.int16) - a[keep]))
        pooled = np.concatenate(changes)
        if pooled.size < NOISE_MIN_PIXELS:
            return
        self._noise.append(float(_median(pooled)))
        self.sensor_noise = 1.4826 * float(np.median(np.fromiter(self._noise, float)))
