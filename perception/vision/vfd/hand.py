"""Hand-tracker: a group of feedback-controlled windows under mutual constraints (Sec. III-C).

Structure (Fig. 4, read in our two views):
- side view: a palm window (GGE: centre of mass of the hand's gray band), two
  finger windows whose offset vectors point away from the palm and reverse
  when they lose their target (Fig. 3), and a holder window kept midway between
  the fingers (it also measures how much block is between them);
- top view: a palm window (GGE).
Each window moves to ``g = f + d`` (feature point plus offset) every frame.
Constraints (Sec. III-C3): each finger stays within a distance range of the
palm, the fingers keep a minimum gap, the palm stays a preset height above the
holder and within a short horizontal range of it. The hand position is the
holder (between the fingers, Table II): its side-view point on the vertical
plane through the triangulated palm. Velocity is a least-squares slope over the
last samples (robust to pixel noise and tremor).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping, Sequence

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.vision.frames import Frame
from perception.vision.vfd.base import BLOCK_MIN, HAND_BAND, VFD, VIEWS, band, centroid
from perception.vision.vfd.resources import VisionResources, Window

# Window sizes (px) and the simplified hand structure (mm) the constraints encode.
PALM_WIN = {"top": (44, 34), "side": (32, 26)}
FINGER_WIN = (14, 16)
HOLDER_WIN = (10, 10)
FINGER_REACH_MM = (15.0, 100.0)  # finger feature distance from the palm feature
FINGER_GAP_MM = 12.0  # fingers never closer than this
PALM_ABOVE_MM = 20.0  # palm at least this far above the holder
PALM_SIDEWAYS_MM = 30.0  # and at most this far sideways from it
MIN_PIXELS = 4  # fewer band pixels than this in a window: target lost
HOLDER_ABOVE_TIPS_MM = 10.0  # the holder (hand centre) sits this far above the fingertips
FINGER_FRONT_MM = 10.0  # the side camera sees the fingertips' front edge, this far forward
HAND_AT_PIXELS = 20  # hand-band pixels around a point that show the hand there (a palm: ~150)
# The holder hangs a fixed drop below the palm (the hand's structure, Sec. III-C3), learned
# while the fingertips are seen. A block standing between the side camera and a lowering
# hand hides the fingertips: the lowest hand row seen is then that block's top, and the
# fingertip height stops falling while the palm goes on down (align bench 1013: 34 mm too
# high for 1.5 s, so the slide that followed was taken for the approach). A drop this much
# shorter than the learned one is such a cut; the palm then gives the height.
OCCLUDED_MM = 6.0
ONE_BAND = 0.7  # share of hand pixels between the finger features: one band (y-jaws; x-jaws
# show 0.1-0.3 there, y-jaws 1.0 on 24 generated demonstrations of every family)
EDGE_ROWS, EDGE_COLS, EDGE_SHARE = 6, 2, 0.5  # the patch under the fingertips (px), and
# the share of a row of it in block faces that shows a block's top hiding them
DROP_RATE = 0.05  # weight of each seen frame in the learned drop (tremor: about 1.5 mm)


# Finger window offsets point away from the palm (Sec. III-C3). The fingers hang below the
# palm, so "away" is down and a little outwards: the window then settles with the
# fingertip inside it (Fig. 3(c)). Half the window long, as in the paper.
_FINGER_OFFSET = {side: tuple((np.array([side * 0.3, 1.0]) / np.hypot(0.3, 1.0)
                               * (FINGER_WIN[1] / 2.0)).tolist()) for side in (-1, 1)}


class _Tracker:
    """One feedback-controlled window: moves to feature + offset, offset reverses on loss.

    Points are (x, y) tuples of floats: every frame moves the five windows several times,
    and 2-vector numpy arithmetic costs a microsecond per operation.
    """

    def __init__(self, window: Window, size: tuple[int, int], image_size: tuple[int, int]) -> None:
        """Wrap an allocated ``window`` of ``size`` (w, h) px."""
        self.window, self.size, self.image_size = window, size, image_size
        self.center: tuple[float, float] = window.center
        self.offset = (0.0, 0.0)
        self.sign = 1.0  # -1 after a loss: the offset is reversed (Fig. 3(d))
        self.feature: tuple[float, float] | None = None
        self.tip = 0.0  # lowest hand row in the window (a fingertip for a finger window)

    def place(self, center: Sequence[float]) -> None:
        """Move the window centre to ``center``."""
        self.center = cx, cy = float(center[0]), float(center[1])
        self.window.move_to(cx, cy, self.size[0], self.size[1], self.image_size)

    def step(self, image: np.ndarray) -> bool:
        """One tracking cycle (Sec. III-C2 steps 1-4); False if the target is lost."""
        w = self.window
        sub = w.read(image)
        mask = cv2.inRange(sub, HAND_BAND[0], HAND_BAND[1])  # 255 in the hand band
        # Centre of mass from the mask's moments: the same GGE feature as vfd.centroid
        # (exact integer sums), in one cv2 call instead of several numpy reductions
        # (this runs for four windows every frame).
        m = cv2.moments(mask, True)
        n = int(m["m00"])
        ox, oy = self.offset
        if n < MIN_PIXELS:
            self.feature = None
            self.offset, self.sign = (-ox, -oy), -self.sign  # Fig. 3(d): local recovery
            self.place((self.center[0] - ox, self.center[1] - oy))
            return False
        cx, cy = m["m10"] / n, m["m01"] / n
        self.feature = fx, fy = (w.x0 + cx, w.y0 + cy)
        per_row = np.add.reduce(mask, axis=1, dtype=np.int32).tolist()  # 255 per pixel
        last = len(per_row) - 1
        while last >= 0 and per_row[last] < 2 * 255:  # a lone noisy pixel is no fingertip
            last -= 1
        self.tip = w.y0 + float(last if last >= 0 else cy)
        self.place((fx + ox, fy + oy))
        return True


class HandTracker(VFD):
    """Tracks the hand; ``target()`` is the 3-D holder position, ``velocity`` in mm/s."""

    def __init__(self, cameras: Mapping[str, Camera], resources: VisionResources,
                 history: int = 7, replace_mm: float = 120.0) -> None:
        """Allocate the palm, finger and holder windows (6 of the 32).

        ``replace_mm``: re-place the tracker when the motion-detector disagrees by more
        (Sec. V-A; rules/constants.yaml ``repositioning-distance``, footnote 12).
        """
        super().__init__(cameras, resources)
        self.replace_mm = float(replace_mm)
        size = {v: self.cameras[v].size for v in VIEWS}
        win = {v: [] for v in VIEWS}
        try:
            for view, n in (("top", 1), ("side", 4)):
                for _ in range(n):
                    win[view].append(resources.allocate(view))
        except Exception:
            for wins in win.values():
                for w in wins:
                    resources.free(w)
            raise
        self.windows = win
        self.palm = {v: _Tracker(win[v][0], PALM_WIN[v], size[v]) for v in VIEWS}
        self.fingers = [_Tracker(win["side"][1], FINGER_WIN, size["side"]),
                        _Tracker(win["side"][2], FINGER_WIN, size["side"])]
        self.holder = _Tracker(win["side"][3], HOLDER_WIN, size["side"])
        self._samples: deque[tuple[float, np.ndarray]] = deque(maxlen=history)
        self.tracking = False
        self.lost_frames = 0
        self.holding_evidence = 0.0  # fraction of block pixels in the holder window
        self.drop: float | None = None  # palm height minus holder height (mm), learned

    # -- placement -------------------------------------------------------------------
    def place(self, xyz: Sequence[float]) -> None:
        """(Re)place the whole tracker at a 3-D point; fingers start beside the palm."""
        p = np.asarray(xyz, float)
        for v in VIEWS:
            self.palm[v].place(self.cameras[v].project(p)[0])
        side = self.cameras["side"]
        s = side.mm_to_px(p)
        cx, cy = self.palm["side"].center
        for sign, f in zip((-1, 1), self.fingers, strict=True):
            f.place((cx + sign * 30.0 * s, cy + 25.0 * s))
            f.offset = (0.0, 0.0)
        self.holder.place((cx + 0.0, cy + 25.0 * s))
        self._samples.clear()
        self.tracking = True
        self.lost_frames = 0
        self.running = True

    def stimulate(self, xyz: Sequence[float] | None, frame: Frame | None = None) -> bool:
        """A motion-detector position: re-place the tracker if it is lost or too far off.

        Sec. V-A re-positions the tracker when the two disagree by more than the
        repositioning distance, because the tracker then follows a false target. The
        motion-detector's point is the centre of everything that moved, though: a
        carried 180 mm beam drags it 100 mm and more off the hand while the tracker is
        right. Given the ``frame``, a tracker that is tracking is therefore re-placed
        only if the hand is really there (hand-band pixels around the point in both
        views), and more of it than around the tracker's own point: the jaws closing on
        the ends of a 160 mm plank move on both sides of the palm, the centre of that
        motion falls on one jaw, and one jaw is hand-gray too (fault bench 7007: the
        tracker was moved 90 mm onto the jaw, so the grip was measured at the plank's
        end and its place on a pillar was taken for the table).
        """
        if xyz is None:
            return False
        if not self.tracking or self._target is None:
            self.place(xyz)
            return True
        if np.linalg.norm(np.asarray(xyz) - self._target) <= self.replace_mm:
            return False
        if frame is not None:
            there = self._hand_pixels(xyz, frame)
            if min(there) < HAND_AT_PIXELS or sum(there) <= sum(
                    self._hand_pixels(self._target, frame)):
                return False
        self.place(xyz)
        return True

    def _hand_pixels(self, xyz: Sequence[float], frame: Frame) -> list[int]:
        """Hand-gray pixels around ``xyz`` in each view (a window the palm's size)."""
        p = np.asarray(xyz, float)
        out = []
        for view in VIEWS:
            w, h = PALM_WIN[view]
            win = self.resources.allocate(view)
            try:
                u, v = self.cameras[view].project(p)[0]
                win.move_to(u, v, w, h, self.cameras[view].size)
                out.append(cv2.countNonZero(cv2.inRange(win.read(frame.view(view)), *HAND_BAND)))
            finally:
                self.resources.free(win)
        return out

    def reset(self) -> None:
        """Forget the position history and stop tracking until placed again."""
        super().reset()
        self._samples.clear()
        self.tracking = False

    # -- per frame -----------------------------------------------------------------------
    def process(self, frame: Frame) -> None:
        """One video-rate cycle of all windows, then constraints and 3-D integration."""
        if not self.tracking:
            return
        side_img = frame.side
        bx, by = self.palm["side"].center
        ok_top = self.palm["top"].step(frame.top)
        ok_side = self.palm["side"].step(side_img)
        mx, my = self.palm["side"].center
        mx, my = mx - bx, my - by
        for f in (*self.fingers, self.holder):  # the palm is their moving reference point
            f.place((f.center[0] + mx, f.center[1] + my))
        if not (ok_top and ok_side):
            self.lost_frames += 1
            if self.lost_frames > 3:
                self.tracking = False  # ENV-node: the hand has disappeared
            return
        self.lost_frames = 0
        side_cam = self.cameras["side"]
        palm3d = self.triangulate(self.palm["top"].feature, self.palm["side"].feature).tolist()
        s = side_cam.mm_to_px(palm3d)
        pf = self.palm["side"].feature
        for side, f in zip((-1, 1), self.fingers, strict=True):
            ox, oy = _FINGER_OFFSET[side]
            f.offset = (f.sign * ox, f.sign * oy)
            if f.step(side_img):
                f.sign = 1.0
            else:
                self._reacquire(f, side, pf, s, side_img)
        self._constrain(pf, s)
        self._measure_holder(side_img)
        # x, y from the stereo palm; height from the fingertips seen from the side.
        good = [f for f in self.fingers
                if f.feature is not None and f.feature[1] > pf[1] + FINGER_REACH_MM[0] * s / 2]
        tips = [f.tip for f in good]
        if len(tips) == 2 and abs(tips[0] - tips[1]) > 2:
            tips = [max(tips)]  # the other one is not at a fingertip: the tips are the lowest
        tip_v = sum(tips) / len(tips) if tips else 0.0
        z = None
        if tips:
            uv = (self.holder.center[0], tip_v)
            front = palm3d[1] - FINGER_FRONT_MM
            z = side_cam.plane_point(uv, 1, front)[2] + HOLDER_ABOVE_TIPS_MM
            z = self._unhidden(z, palm3d[2], side_img, good, tip_v)
        if z is None:
            z = float(palm3d[2]) - self.drop if self.drop is not None else \
                float(self._target[2]) if self._target is not None else float(palm3d[2])
        x = palm3d[0]
        if len(good) == 2 and not self._one_band(side_img, good):
            # the grip centre is midway between the fingers: x from the side
            mid = (good[0].feature[0] + good[1].feature[0]) / 2.0
            x = side_cam.plane_point((mid, tip_v), 1, palm3d[1] - FINGER_FRONT_MM)[0]
        hx = np.array([x, palm3d[1], z])
        self._target = hx
        self._samples.append((frame.t, hx))
        self._found = True

    @staticmethod
    def _one_band(image: np.ndarray, fingers: list[_Tracker]) -> bool:
        """Whether the two finger windows sit on one unbroken hand band: the jaws close
        along y, across the side camera's line of sight, and the front finger hides the
        back one. Their midpoint then lies on a finger 15-30 mm nearer the camera than
        the grip, off by up to 6 mm in x at the table's ends (perspective); the stereo palm
        stands over the grip centre instead (bench 1009: 6.5 mm, with the palm 1 mm).
        With x-jaws a block or the background shows between the fingers."""
        (ax, ay), (bx, by) = fingers[0].feature, fingers[1].feature
        row = image[int(round(min(ay, by))), int(round(min(ax, bx))):int(round(max(ax, bx))) + 1]
        if row.size == 0:
            return True
        hand = cv2.countNonZero(cv2.inRange(row, HAND_BAND[0], HAND_BAND[1]))
        return hand >= ONE_BAND * row.size

    def _unhidden(self, z: float, palm_z: float, image: np.ndarray, fingers: list[_Tracker],
                  tip_v: float) -> float | None:
        """The fingertips' height ``z`` if it agrees with the learned drop below the palm
        (and learn from it), else None: something in front hides the fingertips.

        A block's top edge right under the lowest hand row is what hides them; without
        one the fingertips are seen, however short the drop, and the drop is learned
        from them (a drop once learned too long would otherwise never be corrected).
        """
        drop = float(palm_z) - z
        if self.drop is not None and drop < self.drop - OCCLUDED_MM and \
                self._edge_below(image, fingers, tip_v):
            return None
        self.drop = drop if self.drop is None else self.drop + DROP_RATE * (drop - self.drop)
        return z

    @staticmethod
    def _edge_below(image: np.ndarray, fingers: list[_Tracker], tip_v: float) -> bool:
        """Whether block faces lie right under the lowest hand row, below the fingers (a
        row of them, past the dark edge lines the renderer draws)."""
        rows = slice(int(round(tip_v)) + 1, int(round(tip_v)) + 1 + EDGE_ROWS)
        cols = [int(round(f.feature[0])) for f in fingers]
        patch = image[rows, max(0, min(cols) - EDGE_COLS):max(cols) + EDGE_COLS + 1]
        if patch.size == 0:
            return False
        bright = np.count_nonzero(patch >= BLOCK_MIN, axis=1)  # per row: edges are dark lines
        return bool(bright.max() >= EDGE_SHARE * patch.shape[1])

    def _reacquire(self, f: _Tracker, side: int, pf: tuple[float, float], s: float,
                   image: np.ndarray) -> None:
        """A lost finger looks once along its side below the palm, in a strip as wide as
        its reach (the window is stretched for one read), then returns to its size."""
        x_in, x_out = pf[0], pf[0] + side * FINGER_REACH_MM[1] * s
        y0, y1 = pf[1] + 20.0 * s, pf[1] + 75.0 * s
        w = f.window
        w.move_to((x_in + x_out) / 2.0, (y0 + y1) / 2.0, int(abs(x_out - x_in)) + 1,
                  int(y1 - y0) + 1, f.image_size)
        mask = band(w.read(image), *HAND_BAND)
        c = centroid(mask)
        if c is None or c[2] < MIN_PIXELS:
            f.place(f.center)  # back to its own size; the reversed offset goes on searching
            return
        cols = slice(max(0, int(c[0]) - 4), int(c[0]) + 5)
        rows = np.nonzero(mask[:, cols].sum(axis=1) >= 2)[0]
        f.feature = (w.x0 + c[0], w.y0 + c[1])
        f.tip = w.y0 + float(rows.max() if len(rows) else c[1])
        f.sign = 1.0
        f.place(f.feature)

    def _constrain(self, pf: tuple[float, float], s: float) -> None:
        """Finger reach and gap, holder midway, palm above and near the holder."""
        lo, hi = FINGER_REACH_MM[0] * s, FINGER_REACH_MM[1] * s
        pts = []
        for sign, f in zip((-1, 1), self.fingers, strict=True):
            p = f.feature if f.feature is not None else f.center
            dx, dy = p[0] - pf[0], p[1] - pf[1]
            n = math.sqrt(dx * dx + dy * dy)
            if n < 1e-6:
                dx, dy, n = float(sign), 1.0, math.sqrt(2.0)
            k = min(max(n, lo), hi)
            px, py = pf[0] + dx / n * k, pf[1] + dy / n * k
            if sign * (px - pf[0]) < 0:  # a finger never crosses to the other side
                px = pf[0]
            pts.append([px, py])
        gap = FINGER_GAP_MM * s
        if pts[1][0] - pts[0][0] < gap:
            mid = (pts[0][0] + pts[1][0]) / 2.0
            pts[0][0], pts[1][0] = mid - gap / 2.0, mid + gap / 2.0
        for side, f, (px, py) in zip((-1, 1), self.fingers, pts, strict=True):
            if f.feature is not None:  # the window follows its constrained point
                f.place((f.center[0] + (px - f.feature[0]), f.center[1] + (py - f.feature[1])))
                f.feature = (px, py)
            if side * (f.center[0] - pf[0]) < 1.0:  # a window never crosses under the palm
                f.place((pf[0] + side * 1.0, f.center[1]))
        hx, hy = (pts[0][0] + pts[1][0]) / 2.0, (pts[0][1] + pts[1][1]) / 2.0
        palm = self.palm["side"]
        cx, cy = palm.center
        cy = min(cy, hy - PALM_ABOVE_MM * s)
        cx = min(max(cx, hx - PALM_SIDEWAYS_MM * s), hx + PALM_SIDEWAYS_MM * s)
        palm.place((cx, cy))
        self.holder.place((hx, hy))

    def _measure_holder(self, side_img: np.ndarray) -> None:
        """Fraction of block-white pixels between the fingers (a held object, Sec. III-C3)."""
        sub = self.holder.window.read(side_img)
        white = cv2.countNonZero(cv2.inRange(sub, BLOCK_MIN, 255))
        self.holding_evidence = float(white) / max(1, sub.size)

    # -- queries -------------------------------------------------------------------------
    @property
    def position(self) -> np.ndarray | None:
        """Current 3-D hand (holder) position in mm, or None when not tracking."""
        return self.target() if self.tracking else None

    @property
    def velocity(self) -> np.ndarray:
        """Hand velocity (mm/s): least-squares slope over the recent samples."""
        if len(self._samples) < 3:
            return np.zeros(3)
        t = np.array([s[0] for s in self._samples])
        x = np.array([s[1] for s in self._samples])
        t = t - t.mean()
        return (t @ (x - x.mean(axis=0))) / float(t @ t)
