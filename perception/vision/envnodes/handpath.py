"""The tracked hand's recent path: noise-robust velocity, motion onset and the work region.

Helpers of ``perception.vision.envnodes.hand`` (the HandLoc node and :Far, Table III/IV).
The tracker's positions carry pixel noise and the demonstrator's tremor
(0.4-1.5 Hz); a frame difference of them is dominated by both, so the
velocity is a least-squares slope over a short time window
(``hand-velocity-window`` in rules/constants.yaml). docs/seeing.md explains
the :Far decision that uses ``WorkRegion`` and ``HandPath.onset``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

import numpy as np

HISTORY_S = 1.5  # s of speeds kept to find where the current motion started
ONSET_FRACTION = 0.25  # the onset fit uses the speeds above this share of the current one
PALM_AGREE_MM = 12.0  # the fingers' midpoint and the stereo palm agree within this in x
PALM_FRAMES = 3  # ... unless they disagree on this many frames in a row


class HandPath:
    """Timed 3-D hand positions: velocity over ``window`` s and a short speed history."""

    def __init__(self, window: float) -> None:
        """Velocity from the samples of the last ``window`` seconds."""
        self.window = float(window)
        self.samples: deque[tuple[float, np.ndarray]] = deque()
        self.speeds: deque[tuple[float, float]] = deque()  # (window mid-time, speed)
        self.velocity = np.zeros(3)

    def clear(self) -> None:
        """Forget the path (the tracker was re-placed: old samples are another point)."""
        self.samples.clear()
        self.speeds.clear()
        self.velocity = np.zeros(3)

    def add(self, t: float, p: np.ndarray) -> None:
        """Append a sample; update the velocity (least squares) and the speed history."""
        s = self.samples
        s.append((t, p))
        while t - s[0][0] > self.window + 1e-9:
            s.popleft()
        if len(s) < 3:
            self.velocity = np.zeros(3)
            return
        ts = np.fromiter((q[0] for q in s), float, len(s))
        xs = np.array([q[1] for q in s])
        mid = float(ts.mean())
        ts -= mid
        self.velocity = (ts @ (xs - xs.mean(axis=0))) / float(ts @ ts)
        self.speeds.append((mid, float(np.linalg.norm(self.velocity))))
        while t - self.speeds[0][0] > HISTORY_S:
            self.speeds.popleft()

    def onset(self, now: float) -> float:
        """When the current motion started (at most ``HISTORY_S`` back, never after ``now``).

        A minimum-jerk motion from rest (Sec. V-B's human model: the Transfer leaves
        the end of the Depart at zero speed) speeds up like the square of the time
        since it began, so the square root of the speed grows linearly; the line
        fitted to the recent run of speeds is extrapolated back to zero speed.
        """
        hist = list(self.speeds)
        if not hist:
            return now
        # The motion before (a Depart) ends at rest too: the slowest point of the recent
        # history is the boundary; the fit uses only what came after it.
        m = min(range(len(hist)), key=lambda k: hist[k][1])
        top = max(range(m, len(hist)), key=lambda k: hist[k][1])  # up to the fastest point
        floor = ONSET_FRACTION * hist[top][1]
        run = [(t, v) for t, v in hist[m:top + 1] if v >= floor]
        t_min = hist[m][0]
        if len(run) < 3:
            return min(now, t_min)
        ts = np.array([r[0] for r in run])
        rv = np.sqrt(np.array([r[1] for r in run]))
        slope, cut = np.polyfit(ts, rv, 1)
        if slope <= 0:
            return min(now, t_min)
        return float(np.clip(-cut / slope, t_min, now))


class WorkRegion:
    """The horizontal footprint a LocalMotion works on (its target's box, the place spot)."""

    def __init__(self, lo: Sequence[float], hi: Sequence[float]) -> None:
        """Footprint from corner ``lo`` to ``hi`` (x, y in mm)."""
        self.lo = np.array(lo[:2], float)
        self.hi = np.array(hi[:2], float)

    def extend(self, lo: Sequence[float], hi: Sequence[float]) -> None:
        """Grow the footprint to cover another box (the spot where a block was released)."""
        self.lo = np.minimum(self.lo, np.asarray(lo[:2], float))
        self.hi = np.maximum(self.hi, np.asarray(hi[:2], float))

    def distance(self, p: Sequence[float]) -> float:
        """Horizontal distance (mm) of ``p`` from the footprint, zero above it."""
        d = np.maximum(0.0, np.maximum(self.lo - p[:2], np.asarray(p[:2]) - self.hi))
        return float(np.hypot(d[0], d[1]))


def footprint(boxes: Sequence) -> WorkRegion | None:
    """The joint footprint of 3-D boxes (anything with ``lo``/``hi``), None for none."""
    region = None
    for b in boxes:
        if region is None:
            region = WorkRegion(b.lo, b.hi)
        else:
            region.extend(b.lo, b.hi)
    return region


def median3(points: Sequence[np.ndarray]) -> np.ndarray:
    """Per-axis median of one to three points (np.median costs ~10x more per frame)."""
    if len(points) == 3:
        a, b, c = points
        return np.maximum(np.minimum(a, b), np.minimum(np.maximum(a, b), c))
    return points[0] if len(points) == 1 else (points[0] + points[1]) / 2.0


class PalmCheck:
    """The tracker's hand position, its x checked against the stereo palm.

    The tracker takes x midway between its two finger windows. A finger window that
    lost its finger stays clamped at the palm's side and still looks like a finger;
    the midpoint is then up to half a finger span off (wide grasps: a plank, fingers
    opening at a release; 25-35 mm, seeds 1028 and 1064), for as long as the window
    stays there. The palm sits over the fingers' midpoint, so when the palm seen in
    both views has been more than ``PALM_AGREE_MM`` away in x for ``PALM_FRAMES``
    frames in a row, x comes from the palm. A shorter disagreement is the palm's
    own: its window just after the tracker was re-placed or lost the hand a moment.
    """

    def __init__(self) -> None:
        """No disagreement seen yet."""
        self.frames = 0

    def reset(self) -> None:
        """The tracker was (re)placed: its windows start afresh."""
        self.frames = 0

    def __call__(self, tracker) -> np.ndarray | None:
        """The hand position of this frame (call once per frame)."""
        pos = tracker.position
        if pos is None:
            return None
        top, side = tracker.palm["top"].feature, tracker.palm["side"].feature
        if top is None or side is None:
            self.frames = 0
            return pos
        palm_x = float(tracker.triangulate(top, side)[0])
        self.frames = self.frames + 1 if abs(float(pos[0]) - palm_x) > PALM_AGREE_MM else 0
        if self.frames < PALM_FRAMES:
            return pos
        return np.array([palm_x, float(pos[1]), float(pos[2])])
