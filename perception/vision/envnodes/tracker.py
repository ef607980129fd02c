"""ENV-nodes of the hand (Table III): motion-detector, hand-tracker, hand/object tracker.

* motion-detector, ``moving-target``: a new hand was found moving in the
  workspace (Sec. III-C1, :Found-moving);
* hand-tracker, ``lost``: the tracked hand left the workspace (:Disappeared);
  ``motion-feature``: the hand's 3-D velocity, which the engine turns into a
  Table IV value (:Small-motion, :Large-motion); ``away``: the hand is away
  from the target nodes (:Far);
* hand-object-tracker, ``contact``: the hand, or what it holds, has come down
  onto the target nodes and stays (:Join); ``separation``: it rises from where
  the contact began (:Split).

Each answers from the shared hand state (HandState), the nodes it is given and
the query's ``since`` (when the asking motion began): the stretch of the
hand's path the question is about. docs/seeing.md explains the thresholds.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.names import HAND
from lbw_engine.see.detectors import Detection, Query
from perception.vision.envnodes.base import EnvNodeBase
from perception.vision.envnodes.hand import Sample, box, vec
from perception.vision.envnodes.handpath import WorkRegion, footprint
from perception.vision.vfd.base import Region3D

FAR_RISE_MM = 60.0  # the fast-rise :Far cue needs the hand this far above where it worked
FAR_FRAMES = 2  # :Far holds on this many frames in a row (one-frame height jumps)
FAST_S = 0.1  # s: the fast-rise :Far cue must last this long (tremor peaks are shorter)
JOIN_MM = 10.0  # :Join while the hand stays within this height of its lowest point
DESCENT_MM = 30.0  # ... after coming down at least this far since the motion began
REACHED_MM = 35.0  # :Join needs the hand (held block) within this of the target's top;
# a hesitation on the way down stops well above that (>= 55 mm above the grasp)
SPLIT_MM = 8.0  # :Split once it has risen this much above where it joined


class MotionNode(EnvNodeBase):
    """The World's motion-detector: a new hand entering (:Found-moving, Fig. 10)."""

    name = "motion-detector"
    calls = {"moving-target": "moving_target"}

    def __init__(self, *args: Any) -> None:
        """No hand reported yet."""
        super().__init__(*args)
        self._reported: float | None = None

    def moving_target(self, query: Query, env: EnvModel) -> Detection | None:
        """The hand the always-on motion-detector found since the query began, once."""
        found = self.hand.t_found
        if found is None or found < query.since or found == self._reported:
            return None
        self._reported = found
        return Detection(found=(HAND,), positions={HAND: vec(self.hand.found_at)})


class HandTrackerNode(EnvNodeBase):
    """The HandLoc's hand-tracker: leaving, moving, going away (Sec. III-C2, IV-A)."""

    name = "hand-tracker"
    calls = {"lost": "lost", "motion-feature": "motion_feature", "away": "away"}

    def __init__(self, *args: Any) -> None:
        """No footprint measured yet."""
        super().__init__(*args)
        self._footprint: tuple[Any, WorkRegion | None] = (None, None)

    def lost(self, query: Query, env: EnvModel) -> Detection | None:
        """The tracker lost the hand at the workspace's edge: it went outside (dated then)."""
        return Detection(t=self.hand.t_seen) if self.hand.status == "gone" else None

    def motion_feature(self, query: Query, env: EnvModel) -> Detection | None:
        """The tracker's velocity; the engine classifies it (Table IV)."""
        hand = self.hand
        if not hand.tracking or not hand.steady:
            return None
        return hand.detection(velocity=vec(hand.velocity))

    def away(self, query: Query, env: EnvModel) -> Detection | None:
        """The hand away from the target nodes (Table III :Far), dated at its onset.

        Geometric first: on FAR_FRAMES frames in a row the hand is outside the
        targets' footprint grown by ``far-margin``, or higher above its lowest point
        since the motion began than the guided search reaches. The next target may
        lie in the same footprint (a touch, then a pick of the same block): then a
        Transfer-fast motion (over 2 V_H1, well above a slow depart with tremor),
        kept for FAST_S once the hand has risen FAR_RISE_MM, tells it.
        """
        hand = self.hand
        low = hand.lowest(query.since)
        if not hand.tracking or low is None:
            return None
        work = self._work(query, env, low)
        margin = float(self.rules.constants["far-margin"])
        reach = float(self.rules.constants["search-cycle-limit"]) * float(
            self.rules.constants["attention-region"][2])
        recent = hand.since(hand.sight.t - FAST_S)
        floor = float(low.hand[2])

        def outside(s: Sample) -> bool:
            rise = float(s.hand[2]) - floor
            # where the hand is: its palm-checked spot (a finger window that lost its finger
            # puts the tracker's own point up to half a finger span off: bench 1143 at 4x,
            # a hand opened 141 mm for a slat, 30 mm off while it paused over it)
            return (work is not None and work.distance(s.spot) > margin) or rise > reach

        last = hand.history[-FAR_FRAMES:]
        away = len(last) == FAR_FRAMES and all(outside(s) for s in last)
        # Speeds right after a re-placement are the windows converging, not the hand.
        fast = len(recent) > 1 and recent[0].t <= hand.sight.t - FAST_S and all(
            s.steady and float(s.hand[2]) - floor > FAR_RISE_MM and s.speed > 2 * hand.v_fast
            for s in recent)
        if away or fast:
            return hand.detection(t=hand.path.onset(hand.sight.t))
        top = self._came_back(low)
        if top is not None:
            return hand.detection(t=top.t)
        return None

    def _came_back(self, low: Sample) -> Sample | None:
        """The top of a rise of FAR_RISE_MM above the motion's lowest point ``low``, if the
        hand has come down DESCENT_MM from it since, on FAR_FRAMES frames: it left and is
        coming back to the same footprint (a touch with a block in hand, then its place on
        the touched block; the rise stays under the search's reach and the short transfer
        under the fast cue's speed)."""
        hand = self.hand
        top = hand.highest(low.t)
        if top is None or float(top.hand[2]) - float(low.hand[2]) <= FAR_RISE_MM:
            return None
        last = hand.history[-FAR_FRAMES:]
        drop = float(top.hand[2]) - DESCENT_MM
        if len(last) == FAR_FRAMES and all(s.t > top.t and float(s.hand[2]) < drop
                                           for s in last):
            return top
        return None

    def _work(self, query: Query, env: EnvModel, low: Sample) -> WorkRegion | None:
        """The footprint the motion works on: the held object where it came down and where
        it was let go (a place), else the target blocks (a pick, a touch), else the spot
        under the hand where the motion began."""
        hand = self.hand
        start = hand.at(query.since)
        held = env.held()
        if held:
            let_go = hand.let_go(query.since)
            key = (query.since, held, id(start), id(let_go))
            if self._footprint[0] != key:  # the same question as on the last frame
                boxes = [hand.held_box(env, at=start), hand.held_box(env, at=let_go)]
                self._footprint = (key, footprint([b[1] for b in boxes if b is not None]))
            if self._footprint[1] is not None:
                return self._footprint[1]
            boxes = []
        else:
            boxes = [box(n) for n in query.target if n.kind == "Loc" and n.size is not None
                     and n.position is not None]
        if not boxes:
            boxes = [Region3D.around(start.hand, self.rules.constants["attention-region"])]
        return footprint(boxes)


class ContactNode(EnvNodeBase):
    """The hand/object tracker: the hand or its load touches the target, and leaves it."""

    name = "hand-object-tracker"
    calls = {"contact": "contact", "separation": "separation"}

    def contact(self, query: Query, env: EnvModel) -> Detection | None:
        """The hand staying at its lowest point, come down onto the target (:Join)."""
        hand = self.hand
        start = hand.at(query.since)
        if hand.hand is None or start is None:
            return None
        z = float(hand.hand[2])
        low = float(hand.lowest(query.since).hand[2])
        descent = float(start.hand[2]) - low
        if (hand.speed() < hand.v_slow and z - low < JOIN_MM and descent > DESCENT_MM
                and self._reached(query.target, env)):
            return hand.detection()
        return None

    def _reached(self, target: tuple[EnvNode, ...], env: EnvModel) -> bool:
        """Whether the hand has come down to its target, not paused on the way (a hesitation).

        A held block must have reached the top of what it is put on (its supports, or
        the table); an empty hand the height of the target's top (a grasp holds a block
        below its top face, a touch comes down onto it).
        """
        tops = [n.top() for n in target if n.kind == "Loc" and n.position is not None]
        held = self.hand.held_box(env)
        if held is not None:
            return float(held[1].lo[2]) <= max(tops, default=0.0) + REACHED_MM
        return not tops or float(self.hand.hand[2]) <= max(tops) + REACHED_MM

    def separation(self, query: Query, env: EnvModel) -> Detection | None:
        """The hand risen from where the contact began (:Split)."""
        hand = self.hand
        start = hand.at(query.since)
        if hand.hand is None or start is None:
            return None
        if float(hand.hand[2]) - float(start.hand[2]) > SPLIT_MM:
            return hand.detection()
        return None

