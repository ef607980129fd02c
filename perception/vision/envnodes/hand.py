"""What every image-backed ENV-node shares: the current frame and the tracked hand.

``Sight`` is the infrastructure of Fig. 2 every VFD shares: the two camera
models, the 32-window resource manager and the current frame. ``HandState`` is
the HandLoc node of Table II as the images show it: the always-on
motion-detector and hand-tracker (Sec. III-C, V-A) run on every frame whatever
is asked, and their result is kept as a short timed path of the hand. It is the
only state the ENV-nodes share; each node answers its queries from it, from
the ENV-nodes it is given and from the frame, and keeps nothing another node
reads.

The path answers questions about a stretch of time (``since`` = when the
asking motion began): the lowest point, where the hand let go, the height it
had then. The grip offset of a held object (where it hangs under the hand) is
measured from the path too: at the lowest point of the hand over the object's
resting place before it was held.
"""

from __future__ import annotations

import bisect
from collections import deque
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.names import HAND
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import Detection
from perception.vision.camera import WORKSPACE_HI, WORKSPACE_LO, Camera
from perception.vision.envnodes.handpath import HandPath, PalmCheck, median3
from perception.vision.frames import Frame
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.hand import HandTracker
from perception.vision.vfd.motion import MotionDetector
from perception.vision.vfd.resources import VisionResources

Vec3 = tuple[float, float, float]

BORDER_MM = 40.0  # the hand was lost this close to the workspace's edge: it left (:Disappeared)
REENTRY_S = 0.5  # s after leaving before a moving thing counts as a new hand (no Case-2 echo)
HISTORY_S = 30.0  # s of the hand's path kept (a motion's stretch is a few seconds)
LET_GO_MM = 8.0  # the hand let go at the last point of its path this close to its lowest
GRASP_MARGIN_MM = 20.0  # a grasp is made over the object's footprint grown by this
LEFT_MM = 100.0  # ... in the hand's last visit to it: this far off, the hand had left it
CARRY_TOP_MM = 30.0  # the carry's high part: samples this close to its highest point
CONVERGE_FRAMES = 3  # frames a (re)placed tracker's windows take to pull onto the hand
SETTLE_FRAMES = 5  # tracked frames after convergence before the velocity is trusted


class Grip(NamedTuple):
    """Object centre minus the tracked point (``hand``) and the spot at the grasp, and when."""

    hand: np.ndarray
    spot: np.ndarray
    t: float | None


@dataclass(frozen=True)
class Sample:
    """The hand on one frame: time, tracked point, palm-checked point ("spot"), speed, and
    whether the tracker had followed the hand long enough for that speed to be trusted."""

    t: float
    hand: np.ndarray
    spot: np.ndarray
    speed: float
    steady: bool = True
    # the palm in the top view, at the hand's height (x, y): the top camera looks down on
    # the hand, so no block in front hides it (a slide's length, coplanar.py)
    top: tuple[float, float] | None = None


class Sight:
    """The camera models, the window resource manager and the current frame (Fig. 2)."""

    def __init__(self, cameras: Mapping[str, Camera]) -> None:
        """Both views' cameras; windows come from one 32-window manager."""
        self.cameras = dict(cameras)
        self.resources = VisionResources()
        self.frame: Frame | None = None
        self.t = 0.0
        self.pixels: list[int] = []  # pixels read per frame (benchmark)

    def advance(self, t: float, frame: Frame) -> bool:
        """Make ``frame`` current; False when it already is (every node calls this)."""
        if frame is self.frame:
            return False
        if self.frame is not None:
            self.pixels.append(self.resources.end_frame())
        self.frame, self.t = frame, t
        return True


def box(node: EnvNode, center: Sequence[float] | None = None) -> Region3D:
    """The region of an ENV-node's measured box (optionally moved to ``center``)."""
    return Region3D.around(center if center is not None else node.position, node.size)


def inside(p: Sequence[float], margin: float = 0.0) -> bool:
    """Whether ``p`` lies over the table, ``margin`` mm beyond (or, negative, within) it."""
    return bool(WORKSPACE_LO[0] - margin <= p[0] <= WORKSPACE_HI[0] + margin
                and WORKSPACE_LO[1] - margin <= p[1] <= WORKSPACE_HI[1] + margin)


def vec(p: Iterable[float]) -> Vec3:
    """A plain float triple."""
    x, y, z = (float(c) for c in p)
    return (x, y, z)


class HandState:
    """The tracked hand (HandLoc, Table II): status, timed path and grip, from images."""

    def __init__(self, sight: Sight, rules: RuleSet) -> None:
        """The always-on motion-detector and hand-tracker on ``sight``'s windows."""
        constants = rules.constants
        self.sight = sight
        self.motion = MotionDetector(sight.cameras, sight.resources,
                                     interval=float(constants["motion-detector-interval"]))
        self.motion.start()
        self.tracker = HandTracker(sight.cameras, sight.resources,
                                   replace_mm=float(constants["repositioning-distance"]))
        low, high = rules.motion_features.ranges[next(iter(rules.motion_features.ranges))]
        self.v_slow, self.v_fast = float(low), float(high)  # V_L1, V_H1 (footnote 11)
        self.status = "absent"  # absent | tracking | lost | gone
        self.t_gone = -1e9
        self.t_seen = 0.0  # last frame the tracker saw the hand
        self.t_found: float | None = None  # when the current hand was found (a new one)
        self.found_at: np.ndarray | None = None
        self.moving: np.ndarray | None = None  # the motion-detector's latest point
        self.settled = 0  # frames tracked since the tracker was (re)placed
        self.path = HandPath(float(constants["hand-velocity-window"]))
        self.raw: deque[np.ndarray] = deque(maxlen=3)  # last tracker positions (median of 3)
        self.checked: deque[np.ndarray] = deque(maxlen=3)  # the same, x checked by the palm
        self.palm_check = PalmCheck()
        self.hand: np.ndarray | None = None  # tracked 3-D hand position this frame
        self.spot: np.ndarray | None = None  # the same, x from the palm where they disagree
        self.velocity = np.zeros(3)
        self.history: list[Sample] = []  # the path, oldest first (HISTORY_S of it)
        self._times: list[float] = []  # the samples' times, for bisection
        # (since, -1 lowest | 1 highest) -> (samples seen, that sample)
        self._extremes: dict[tuple[float, float], tuple[int, Sample]] = {}
        self._rest: dict[str, np.ndarray] = {}  # object -> its last position while not held
        self._grip: dict[str, Grip] = {}  # held -> its grip, measured when it was picked up
        self._observed: tuple | None = None  # what observe() last saw (frame, relations)

    # -- per frame (always on, Sec. V-A) ----------------------------------------------
    def update(self, t: float, frame: Frame) -> None:
        """Run the motion-detector and the hand-tracker on a new frame, once."""
        if not self.sight.advance(t, frame):
            return
        self.motion.update(frame)
        self.moving = self.motion.target() if self.motion.found() else None
        self._follow_motion(t)
        self.tracker.update(frame)
        self.settled += 1
        if self.status == "tracking" and not self.tracker.tracking:
            gone = self.hand is None or not inside(self.hand, -BORDER_MM)
            self.status, self.t_gone = ("gone", t) if gone else ("lost", self.t_gone)
        if self.settled <= CONVERGE_FRAMES:
            # A re-placement puts the windows where the motion-detector saw motion, which
            # may be off the fingers (the wrist, a settling block): until they have pulled
            # onto the hand their points are not the hand's path, and a velocity fitted
            # across that jump reads as a fast motion (a false :Far on a slow depart).
            self.path.clear()
            self.raw.clear()
            self.checked.clear()
            self.palm_check.reset()
        if self.tracker.tracking and self.tracker.position is not None:
            self._sample(t)
        self._acquire(t)

    def _follow_motion(self, t: float) -> None:
        """Keep the tracker on the hand the motion-detector sees (Sec. V-A, Fig. 10)."""
        if self.moving is None:
            return
        if self.status == "tracking":
            if self.tracker.stimulate(self.moving, self.sight.frame):  # too far off (fn. 12)
                self.settled = 0
        elif self.status == "lost" and inside(self.moving):
            self.tracker.place(self.moving)  # the same hand, found again: not a new one
            self.status, self.settled = "tracking", 0

    def _acquire(self, t: float) -> None:
        """A moving thing inside the workspace while no hand is tracked is a new hand:
        the tracker is placed on it and follows it from the next frame (Sec. III-C1)."""
        if self.moving is None or self.status not in ("absent", "gone"):
            return
        if self.status == "gone" and t - self.t_gone < REENTRY_S:
            return
        if inside(self.moving, BORDER_MM):
            self.tracker.place(self.moving)
            self.status, self.settled = "tracking", 0
            self.hand = np.asarray(self.moving, float)
            self.t_found, self.found_at = t, self.hand.copy()

    def _sample(self, t: float) -> None:
        """Record this frame's hand: median of three (single-frame jumps), palm-checked x."""
        # A finger window may snap to a neighbouring edge for a frame (z jumps of a few
        # cm beside carried blocks); the median of three drops such single-frame jumps.
        self.raw.append(self.tracker.position)
        self.checked.append(self.palm_check(self.tracker))
        self.t_seen = t
        self.hand = median3(self.raw)
        # Where a held block hangs or was let go: x from the palm when the finger windows
        # disagree with it (handpath.PalmCheck). The path, the speeds and heights keep the
        # tracker's own point: a switch between the two is a jump.
        self.spot = median3(self.checked)
        self.path.add(t, self.hand)
        self.velocity = self.path.velocity
        palm = self.tracker.palm["top"].feature
        top = None if palm is None else \
            self.sight.cameras["top"].plane_point(palm, 2, float(self.hand[2]))[:2]
        self.history.append(Sample(t, self.hand, self.spot, self.speed(), self.steady, top))
        self._times.append(t)
        if t - self._times[0] > 2 * HISTORY_S:  # trim in chunks: O(1) per frame on average
            cut = bisect.bisect_left(self._times, t - HISTORY_S)
            del self.history[:cut], self._times[:cut]
            self._extremes.clear()

    # -- the hand now ------------------------------------------------------------------
    @property
    def tracking(self) -> bool:
        """Whether a hand is being tracked."""
        return self.status == "tracking" and self.hand is not None

    @property
    def steady(self) -> bool:
        """Whether the tracker has followed the hand long enough to trust its velocity."""
        return self.settled >= CONVERGE_FRAMES + SETTLE_FRAMES - 1

    def speed(self) -> float:
        """Current hand speed (mm/s)."""
        return float(np.linalg.norm(self.velocity))

    def detection(self, **kw: Any) -> Detection:
        """A detection carrying the measured hand position (HandLoc, Table II)."""
        pos = {HAND: vec(self.hand)} if self.hand is not None else {}
        return Detection(positions=pos, **kw)

    # -- the hand's path since a time ----------------------------------------------------
    def since(self, t: float) -> list[Sample]:
        """The path from time ``t`` on (with the last sample before it, if any)."""
        return self.history[max(0, bisect.bisect_right(self._times, t) - 1):]

    def lowest(self, t: float) -> Sample | None:
        """The lowest point of the path since ``t`` (kept up to date per ``t`` asked)."""
        return self._extreme(t, -1.0)

    def highest(self, t: float) -> Sample | None:
        """The highest point of the path since ``t`` (kept up to date per ``t`` asked)."""
        return self._extreme(t, 1.0)

    def _extreme(self, t: float, sign: float) -> Sample | None:
        """The lowest (``sign`` -1) or highest (1) point since ``t``, scanning only the
        samples added since the same question was last asked."""
        start = max(0, bisect.bisect_right(self._times, t) - 1)
        seen, best = self._extremes.get((t, sign), (start, None))
        for s in self.history[seen:]:
            if best is None or sign * (s.hand[2] - best.hand[2]) > 0:
                best = s
        self._extremes[(t, sign)] = (len(self.history), best)
        if len(self._extremes) > 64:  # old questions are not asked again
            self._extremes.pop(next(iter(self._extremes)))
        return best

    def at(self, t: float) -> Sample | None:
        """The sample at time ``t`` (the last one before it; the first after it if none)."""
        if not self.history:
            return None
        return self.history[max(0, bisect.bisect_right(self._times, t) - 1)]

    def let_go(self, t: float) -> Sample | None:
        """Where the hand let go since ``t``: its last point near the lowest one.

        Fingers open at the bottom of a place, so the release is the last moment the
        hand was still within LET_GO_MM of its lowest point; after it the hand rises.
        """
        low = self.lowest(t)
        if low is None:
            return None
        near = float(low.hand[2]) + LET_GO_MM
        for s in reversed(self.history):
            if s.hand[2] <= near or s is low:
                return s
        return low

    # -- what the hand holds (the HandLoc subnode, Fig. 8) --------------------------------
    def observe(self, env: EnvModel) -> None:
        """Note where each object rests and measure the grip of a newly held one."""
        key = (len(env.relations), env.relations[-1] if env.relations else None)
        if key == self._observed:
            return  # nothing moved since the last look: objects move only by effects
        self._observed = key
        held = set(env.held())
        for name in [n for n in self._grip if n not in held]:
            del self._grip[name]
        for node in env.objects():
            if node.position is None:
                continue
            if node.name not in held:
                self._rest[node.name] = np.asarray(node.position, float)
            elif node.name not in self._grip and node.name in self._rest:
                self._grip[node.name] = self._measure_grip(node)

    def _measure_grip(self, node: EnvNode) -> Grip:
        """Object centre minus the hand (and the spot) where, and when, the hand closed on
        it."""
        rest = self._rest[node.name]
        half = np.asarray(node.size[:2], float) / 2.0 + GRASP_MARGIN_MM
        # the hand's last visit to it, since it was last LEFT_MM away: a neighbour 1 mm
        # away picked 30 s before had the hand as low over the same grown footprint, and
        # that older grasp was taken (the grip 31 mm off, the place on a cube read as on
        # the table: round 18, r58). Not its last stay over it: squeezing in between
        # neighbours, the tracked point may stray off it for a while (v04z).
        over: list[Sample] = []
        for s in reversed(self.history):
            if np.all(np.abs(s.hand[:2] - rest[:2]) <= half):
                over.append(s)
            elif over and float(np.hypot(*(s.hand[:2] - rest[:2]))) > LEFT_MM:
                break
        over = over or list(self.history)
        if not over:
            return Grip(np.zeros(3), np.zeros(3), None)
        grasp = min(over, key=lambda s: float(s.hand[2]))
        return Grip(rest - grasp.hand, rest - grasp.spot, grasp.t)

    def lifted(self, picked: list[EnvNode]) -> dict[str, tuple[float, ...]]:
        """Where the centre of the block the hand has just picked up (the first of
        ``picked``) is now: the hand plus the grip it closed with; {} without the hand or
        the block's rest position."""
        node = picked[0] if picked else None
        if self.hand is None or node is None or node.name not in self._rest:
            return {}
        return {node.name: tuple(float(v) for v in self.hand + self._measure_grip(node).hand)}

    def held_fill(self, box: Region3D) -> float:
        """Share of the holder window that the side-view image of a held block's ``box``
        covers (its bounding rectangle: the robot's 16 mm cube showed 0.2 of it, helper
        round 5's t10, where HOLDING asks 0.6 and the place was missed)."""
        w = self.tracker.holder.window
        lo, hi = box.lo, box.hi
        uv = self.sight.cameras["side"].project(np.array(
            [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]))
        (u0, v0), (u1, v1) = uv.min(axis=0), uv.max(axis=0)
        cover = max(0.0, min(u1, w.x1) - max(u0, w.x0)) * max(0.0, min(v1, w.y1) - max(v0, w.y0))
        return float(cover) / max(1, (w.x1 - w.x0) * (w.y1 - w.y0))

    def held_box(self, env: EnvModel, at: Sample | None = None, spot: bool = False
                 ) -> tuple[EnvNode, Region3D] | None:
        """The held object and its box under the hand (now, or at sample ``at``).

        ``spot`` hangs it under the palm-checked point (where things are, docs/seeing.md)
        instead of the tracker's own point.
        """
        held = [env.nodes[n] for n in env.held() if n in env.nodes]
        if not held or held[0].size is None or self.hand is None:
            return None
        self.observe(env)
        grip = self._grip.get(held[0].name)
        if grip is None:
            return None
        point = (at.spot if spot else at.hand) if at is not None else \
            (self.spot if spot and self.spot is not None else self.hand)
        return held[0], box(held[0], point + grip[1 if spot else 0])

    def top_offset(self, name: str, t: float) -> np.ndarray | None:
        """The top-view palm minus the tracked point, x, y, in the median over the high
        part of the carry of held ``name`` before ``t``, where nothing hides the hand from
        either camera; None with fewer than 3 such samples."""
        grip = self._grip.get(name)
        if grip is None or grip.t is None:
            return None
        carry = [s for s in self.history[bisect.bisect_left(self._times, grip.t):
                                         bisect.bisect_right(self._times, t)] if s.top is not None]
        if not carry:
            return None
        high = max(float(s.hand[2]) for s in carry) - CARRY_TOP_MM
        d = [np.asarray(s.top) - s.hand[:2] for s in carry if s.hand[2] >= high]
        return np.median(np.array(d), axis=0) if len(d) >= 3 else None
