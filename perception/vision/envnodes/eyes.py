"""Perception-backed ENV-node answers: the Table III events from the VFDs (Sec. III, V-A).

One ``Eyes`` object owns the visual feature detectors of docs/vision.md (all
windows come from one 32-window resource manager) and reads each frame once.
Thin adapters in envnodes_adapters.py, one per detector name of rules/events.yaml,
implement the engine's ``Detector`` protocol (lbw_engine/see/detectors.py) on top of it:

| detector            | events / diffs                           | VFDs used                  |
|---------------------|------------------------------------------|----------------------------|
| object-finder       | loc-exist                                | ObjectFinder               |
| motion-detector     | found-moving                             | MotionDetector, HandTracker|
| hand-tracker        | disappeared, small/large-motion, far     | HandTracker                |
| visual-search       | near (guided search, Sec. III-E)         | SilFinder                  |
| hand-object-tracker | join, split                              | HandTracker                |
| change-detector     | SilDiff snapshots (Table V)              | ChangeDetector             |
| coplanar-detector   | CoplDet snapshots (Table V, ALIGN)       | CoplanarDetector           |

Only frames, the camera models, the shape database and the environment model
the engine keeps are read here; docs/seeing.md explains each decision.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from lbw_engine.model.env import HAND, TABLE, EnvModel, EnvNode
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import Detection, ObjectInfo
from perception.vision.camera import WORKSPACE_HI, WORKSPACE_LO, Camera
from perception.vision.envnodes.handpath import HandPath, PalmCheck, footprint, median3
from perception.vision.envnodes.search import SearchNode
from perception.vision.envnodes.snapshots import ChangeNode, CoplanarNode, box, held_box
from perception.vision.frames import Frame
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.hand import HandTracker
from perception.vision.vfd.motion import MotionDetector
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources

Vec3 = tuple[float, float, float]

NAME_RADIUS = 40.0  # mm: a found object takes a teach name within this distance (same shape)
BORDER_MM = 40.0  # the hand was lost this close to the workspace's edge: it left (:Disappeared)
REENTRY_S = 0.5  # s after leaving before a moving thing counts as a new hand (no Case-2 echo)
FAR_RISE_MM = 60.0  # the fast-rise :Far cue needs the hand this far above where it worked
JOIN_MM = 10.0  # :Join while the hand stays within this height of its lowest point
DESCENT_MM = 30.0  # ... after coming down at least this far since :Near
SETTLE_FRAMES = 5  # tracked frames after a (re)placement before the velocity is trusted
FAR_FRAMES = 2  # :Far holds on this many frames in a row (one-frame height jumps)
FAST_S = 0.1  # s: the fast-rise :Far cue must last this long (tremor peaks are shorter)
REACHED_MM = 35.0  # :Join needs the hand (held block) within this of the target's top;
# a hesitation on the way down stops well above that (>= 55 mm above the grasp)
MIN_TRANSFER_S = 0.3  # a Transfer (hand lifted, carried, slowed above a target) lasts longer
NEAR_SPEED = 1.5  # :Near only while the hand is slower than this many V_H1 (arriving)
SPLIT_MM = 8.0  # :Split once it has risen this much above where it joined


class Eyes:
    """The VFDs behind the ENV-nodes, fed one frame at a time (online, causal)."""

    def __init__(self, cameras: Mapping[str, Camera], shapes: Mapping[str, Sequence[float]],
                 rules: RuleSet, names: Mapping[str, tuple[str, Sequence[float]]] | None = None
                 ) -> None:
        """Detectors on ``cameras``; ``shapes`` is the shape database; ``names`` a naming hint."""
        self.cameras, self.rules = dict(cameras), rules
        self.shapes = {k: tuple(float(v) for v in s) for k, s in shapes.items()}
        self.names = dict(names or {})
        self.resources = VisionResources()
        self.motion = MotionDetector(self.cameras, self.resources,
                                     interval=float(rules.constants["motion-detector-interval"]))
        self.motion.start()
        self.tracker = HandTracker(self.cameras, self.resources)
        self.objects = ObjectFinder(self.cameras, self.resources)
        low, high = rules.motion_features.ranges[next(iter(rules.motion_features.ranges))]
        self.v_slow, self.v_fast = float(low), float(high)  # V_L1, V_H1 (footnote 11)
        self.frame: Frame | None = None
        self.t = 0.0
        self.hand: np.ndarray | None = None  # tracked 3-D hand position this frame
        self.velocity = np.zeros(3)
        self.state = "absent"  # absent | tracking | lost | gone
        self.t_gone = -1e9
        self.t_seen = 0.0  # last frame the tracker saw the hand
        self.moving: np.ndarray | None = None  # the motion-detector's latest point
        self.low: float | None = None  # lowest hand height since the last :Near
        self.high: float | None = None  # hand height at the last :Near
        self.off_frames = 0  # frames in a row the hand was outside the work region (:Far)
        self.fast_since: float | None = None  # since when it has been rising fast (:Far)
        self.settled = 0  # frames tracked since the tracker was (re)placed
        self.path = HandPath(float(rules.constants["hand-velocity-window"]))
        self.far_margin = float(rules.constants["far-margin"])
        # :Far by height: beyond the guided search's reach (cycle limit x region height)
        self.far_height = float(rules.constants["search-cycle-limit"]) * float(
            rules.constants["attention-region"][2])
        self.work = footprint([])  # footprint of this LocalMotion's target
        self.raw: deque[np.ndarray] = deque(maxlen=3)  # last tracker positions (median of 3)
        self.palm_check = PalmCheck()  # hand x against the stereo palm
        self.checked: deque[np.ndarray] = deque(maxlen=3)  # the same, x checked by the palm
        self.spot: np.ndarray | None = None  # hand position for where things are (docs)
        self.joined_at: float | None = None  # hand height at the last :Join
        self.release: np.ndarray | None = None  # hand position at the last :Split
        self.t_far = -np.inf  # when :Far last fired (a Transfer began)
        self.released: Region3D | None = None  # box of the block let go at the last :Split
        self.grip = np.zeros(3)  # held block centre minus hand, measured at the grasp
        self.spot_grip = np.zeros(3)  # the same from ``spot``
        self.pixels: list[int] = []  # pixels read per frame (benchmark)
        self.search = SearchNode(self)
        self.change = ChangeNode(self)
        self.coplanar = CoplanarNode(self)

    # -- per frame -----------------------------------------------------------------
    def begin_frame(self, t: float, frame: Frame) -> None:
        """Run the always-on detectors (motion, hand tracking) on a new frame, once."""
        if frame is self.frame:
            return
        if self.frame is not None:
            self.pixels.append(self.resources.end_frame())
        self.frame, self.t = frame, t
        self.motion.update(frame)
        self.moving = self.motion.target() if self.motion.found() else None
        if self.moving is not None and self.state == "tracking":
            if self.tracker.stimulate(self.moving):  # re-placed: > 120 mm off (Sec. V-A)
                self.settled = 0
        elif self.moving is not None and self.state == "lost" and _inside(self.moving):
            self.tracker.place(self.moving)  # the same hand, found again: not a new one
            self.state, self.settled = "tracking", 0
        self.tracker.update(frame)
        self.settled += 1
        if self.state == "tracking" and not self.tracker.tracking:
            gone = self.hand is None or not _inside(self.hand, -BORDER_MM)
            self.state, self.t_gone = ("gone", t) if gone else ("lost", self.t_gone)
        if self.settled == 1:
            self.path.clear()
            self.raw.clear()
            self.checked.clear()
            self.palm_check.reset()
        if self.tracker.tracking and self.tracker.position is not None:
            # A finger window may snap to a neighbouring edge for a frame (z jumps of a few
            # cm beside carried blocks); the median of three drops such single-frame jumps.
            self.raw.append(self.tracker.position)
            self.checked.append(self.palm_check(self.tracker))
            self.t_seen = t
            self.hand = median3(self.raw)
            # Where a held block hangs or was let go: x from the palm when the finger
            # windows disagree with it (envnodes_hand.PalmCheck). The path, the speeds and
            # heights keep the tracker's own point: a switch between the two is a jump.
            self.spot = median3(self.checked)
            self.path.add(t, self.hand)
            self.velocity = self.path.velocity
            if self.low is not None:
                self.low = min(self.low, float(self.hand[2]))

    def speed(self) -> float:
        """Current hand speed (mm/s)."""
        return float(np.linalg.norm(self.velocity))

    def hand_detection(self, **kw: Any) -> Detection:
        """A detection carrying the measured hand position (HandLoc, Table II)."""
        pos = {HAND: _vec(self.hand)} if self.hand is not None else {}
        return Detection(positions=pos, **kw)

    # -- :Loc-exist ------------------------------------------------------------------------
    def locate(self) -> Detection | None:
        """The object-finder's initial state, named per design.md."""
        found = self.objects.find(self.frame, self.shapes)
        if not found:
            return None
        taken: set[str] = set()
        counts: dict[str, int] = {}
        out: dict[str, ObjectInfo] = {}
        for obj in sorted(found, key=lambda o: (o.position[0], o.position[1])):
            name = self._teach_name(obj.shape, obj.position, taken)
            if name is None:
                counts[obj.shape] = counts.get(obj.shape, 0) + 1
                name = f"{obj.shape}{counts[obj.shape]}"
                while name in self.names or name in out:
                    counts[obj.shape] += 1
                    name = f"{obj.shape}{counts[obj.shape]}"
            taken.add(name)
            out[name] = ObjectInfo(obj.shape, self.shapes.get(obj.shape, obj.size), obj.position)
        return Detection(found=tuple(out), objects=out)

    def _teach_name(self, shape: str, pos: Sequence[float], taken: set[str]) -> str | None:
        """The hint's name of the same shape nearest to ``pos`` (within NAME_RADIUS)."""
        best, dist = None, NAME_RADIUS
        for name, (s, at) in self.names.items():
            d = float(np.hypot(pos[0] - at[0], pos[1] - at[1]))
            if s == shape and name not in taken and d <= dist:
                best, dist = name, d
        return best

    # -- :Found-moving, :Disappeared -------------------------------------------------------
    def found_moving(self) -> Detection | None:
        """A moving thing inside the workspace while no hand is tracked: a new hand."""
        if self.state not in ("absent", "gone") or self.moving is None:
            return None
        if self.state == "gone" and self.t - self.t_gone < REENTRY_S:
            return None
        if not _inside(self.moving, BORDER_MM):
            return None
        self.tracker.place(self.moving)
        self.state, self.hand, self.settled = "tracking", np.asarray(self.moving, float), 0
        return Detection(found=(HAND,), positions={HAND: _vec(self.moving)})

    def disappeared(self) -> Detection | None:
        """The tracked hand was lost at the workspace's edge: it went outside the world."""
        # The tracker gives up a few frames after it last saw the hand: it left then.
        return Detection(t=self.t_seen) if self.state == "gone" else None

    # -- :Far, :Join, :Split -------------------------------------------------------------------
    def far(self) -> Detection | None:
        """The hand away from the LocalMotion's target (Table III :Far), dated at its onset.

        Geometric first: the hand is outside the target's footprint grown by
        ``far-margin``, or higher above where it worked than the guided search
        reaches. The next target may lie in the same footprint (a touch, then a
        pick of the same block): then a Transfer-fast motion (over 2 V_H1, well
        above a slow depart with tremor) once the hand has risen tells it.
        """
        if self.hand is None or self.low is None or self.state != "tracking":
            return None
        rise = float(self.hand[2]) - self.low
        outside = (self.work is not None and self.work.distance(self.hand) > self.far_margin) \
            or rise > self.far_height
        if not (rise > FAR_RISE_MM and self.speed() > 2 * self.v_fast):
            self.fast_since = None
        elif self.fast_since is None:
            self.fast_since = self.t
        # tremor (with the depart's rise) reaches 2 V_H1 for moments; a Transfer keeps it up
        fast = self.fast_since is not None and self.t - self.fast_since >= FAST_S
        self.off_frames = self.off_frames + 1 if outside else 0
        if self.off_frames >= FAR_FRAMES or fast:
            self.low, self.work, self.fast_since = None, None, None
            self.t_far = self.t
            return self.hand_detection(t=self.path.onset(self.t))
        return None

    def join(self, target: Sequence[EnvNode], env: EnvModel) -> Detection | None:
        """Hand staying at its lowest point (touching the target)."""
        if self.hand is None or self.low is None:
            return None
        if (self.speed() < self.v_slow and self.hand[2] - self.low < JOIN_MM
                and self.high - self.low > DESCENT_MM and self.reached(target, env)):
            self.joined_at = float(self.hand[2])
            locs = [n for n in target if n.kind == "Loc" and n.position is not None]
            if not env.held() and len(locs) == 1:  # where a grasp would hold it
                self.grip = np.asarray(locs[0].position, float) - self.hand
                self.spot_grip = np.asarray(locs[0].position, float) - self.spot
            return self.hand_detection()
        return None

    def reached(self, target: Sequence[EnvNode], env: EnvModel) -> bool:
        """Whether the hand has come down to its target, not paused on the way (a hesitation).

        A held block must have reached the top of what it is put on (its supports, or
        the table); an empty hand the height of the target's top (a grasp holds a block
        below its top face, a touch comes down onto it).
        """
        tops = [n.top() for n in target if n.kind == "Loc" and n.position is not None]
        held = held_box(self, env)
        if held is not None:
            return float(held[1].lo[2]) <= max(tops, default=0.0) + REACHED_MM
        return not tops or float(self.hand[2]) <= max(tops) + REACHED_MM

    def split(self, env: EnvModel) -> Detection | None:
        """Hand rising away from where it joined."""
        if self.hand is None or self.joined_at is None:
            return None
        if self.hand[2] - self.joined_at > SPLIT_MM:
            joined, self.joined_at = self.joined_at, None
            self.release = self.spot.copy()
            held = held_box(self, env)
            if held is not None:  # the block stays where it was let go, the hand's rise below
                self.released = held[1].shifted(dz=-(float(self.hand[2]) - joined))
            if held is not None and self.work is not None:  # the spot where it was let go
                self.work.extend(held[1].lo, held[1].hi)
            return self.hand_detection()
        return None

    def near_found(self, found: Sequence[str], env: EnvModel) -> None:
        """A LocalMotion starts: track the hand's lowest point and its target's footprint.

        The footprint is the held block's (a place: where it comes down) or the found
        blocks' boxes as they are now (a pick: where the target was before it moved).
        """
        self.low = float(self.hand[2]) if self.hand is not None else None
        self.high, self.release, self.released = self.low, None, None
        held = held_box(self, env)
        boxes = [held[1]] if held is not None else [
            box(n) for n in env.get(tuple(found)) if n.kind == "Loc" and n.size is not None]
        if not boxes and self.hand is not None:  # the table, empty-handed: around the hand
            boxes = [Region3D.around(self.hand, self.search.default)]
        self.work = footprint(boxes)


def _inside(p: Sequence[float], margin: float = 0.0) -> bool:
    """Whether ``p`` lies over the table, ``margin`` mm beyond (or, negative, within) it."""
    return bool(WORKSPACE_LO[0] - margin <= p[0] <= WORKSPACE_HI[0] + margin
                and WORKSPACE_LO[1] - margin <= p[1] <= WORKSPACE_HI[1] + margin)


def _vec(p: Iterable[float]) -> Vec3:
    """A plain float triple."""
    x, y, z = (float(c) for c in p)
    return (x, y, z)


__all__ = ["Eyes", "TABLE"]
