"""Detector adapters: one per detector name of rules/events.yaml, on top of ``Eyes``.

Each adapter implements the engine's ``Detector`` protocol (lbw_engine/see/detectors.py)
by asking the shared ``Eyes`` of perception/vision/envnodes/eyes.py (the table there lists which
VFDs answer which events); ``watch_frames`` wires them into a ``Recognizer`` and runs it
online over a frame source.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.model.env import EnvModel
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import ActView, Detection, DetectorRegistry, Query
from lbw_engine.see.recognizer import Recognizer
from perception.vision.camera import Camera
from perception.vision.envnodes.eyes import MIN_TRANSFER_S, NEAR_SPEED, SETTLE_FRAMES, Eyes, _vec
from perception.vision.envnodes.snapshots import ChangeNode, CoplanarNode
from perception.vision.frames import Frame


class _Node:
    """Adapter: one detector name of the rules answering through the shared Eyes."""

    calls: dict[str, str] = {}  # detector method (its vocabulary) -> Python method
    answers: frozenset = frozenset()

    def __init__(self, eyes: Eyes, name: str) -> None:
        """Serve detector ``name``."""
        self.eyes, self.name = eyes, name
        self.methods = frozenset(self.calls)

    def begin_frame(self, t: float, frame: Any) -> None:
        """Feed the frame to the shared detectors (once per frame)."""
        self.eyes.begin_frame(t, frame)

    def query(self, query: Query, env: EnvModel) -> Detection | None:
        """Answer the query's method from the VFDs."""
        method = self.calls.get(query.method)
        if method is None:
            raise InputError(f"detector {self.name!r} cannot answer {query.method!r} "
                             f"(asked for the event {query.event!r})")
        return getattr(self, method)(query.base, query.target, env)

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """No snapshot for this detector."""
        return None

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """Nothing to compare."""
        return None


class _Objects(_Node):
    calls = {"locate": "loc_exist"}

    def loc_exist(self, base, target, env) -> Detection | None:
        """Object-finder: identify and locate the objects (Sec. III-B)."""
        return self.eyes.locate()


class _Motion(_Node):
    calls = {"moving-target": "found_moving"}

    def found_moving(self, base, target, env) -> Detection | None:
        """Motion-detector: a new moving hand (Sec. III-C1)."""
        return self.eyes.found_moving()


class _Hand(_Node):
    calls = {"lost": "disappeared", "away": "far", "motion-feature": "motion_value"}

    def disappeared(self, base, target, env) -> Detection | None:
        """Hand-tracker lost the hand at the edge."""
        return self.eyes.disappeared()

    def far(self, base, target, env) -> Detection | None:
        """Hand away from the target."""
        return self.eyes.far()

    def motion_value(self, base, target, env) -> Detection | None:
        """HandLoc: the tracker's velocity; the engine classifies it (Table IV)."""
        eyes = self.eyes
        if eyes.hand is None or eyes.state != "tracking" or eyes.settled < SETTLE_FRAMES:
            return None
        return eyes.hand_detection(velocity=_vec(eyes.velocity))


class _HandObject(_Node):
    calls = {"contact": "join", "separation": "split"}

    def join(self, base, target, env) -> Detection | None:
        """Hand (with what it holds) touches the target."""
        return self.eyes.join(target, env)

    def split(self, base, target, env) -> Detection | None:
        """Hand leaves the target."""
        return self.eyes.split(env)


class _Search(_Node):
    calls = {"visual-search": "near"}

    def near(self, base, target, env) -> Detection | None:
        """Guided visual search below the hand, confirmed in the env model (Sec. III-E)."""
        eyes = self.eyes
        if (eyes.settled < SETTLE_FRAMES or eyes.speed() > NEAR_SPEED * eyes.v_fast
                or eyes.t - eyes.t_far < MIN_TRANSFER_S):
            # a hand that stopped once and sped on (leaving) is not arriving, nor one whose
            # Transfer has only just begun; just after a re-placement its velocity is unknown
            return None
        found = self.eyes.search.near(env)
        if found:
            self.eyes.near_found(found, env)
            return self.eyes.hand_detection(found=found)
        return None


class _Snapshots(_Node):
    """Snapshot/compare adapter for a VFD node with ``snapshot``/``compare``."""

    def __init__(self, eyes: Eyes, name: str, node: Any) -> None:
        """Serve snapshots through ``node``."""
        super().__init__(eyes, name)
        self.node = node
        self.answers = frozenset(node.answers)

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """Take the VFD's snapshot of the current frame for ``act``."""
        return self.node.snapshot(act, env)

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """The VFD's qualitative change between the two snapshots."""
        return self.node.compare(first, last, act, env)

    def pending(self, last: Any) -> bool:
        """Whether the VFD cannot judge this end snapshot yet (the engine asks again later)."""
        pending = getattr(self.node, "pending", None)
        return bool(pending is not None and pending(last))


def perception_detectors(eyes: Eyes) -> dict[str, Any]:
    """Detector name (rules/events.yaml) -> perception-backed Detector."""
    return {
        "object-finder": _Objects(eyes, "object-finder"),
        "motion-detector": _Motion(eyes, "motion-detector"),
        "hand-tracker": _Hand(eyes, "hand-tracker"),
        "visual-search": _Search(eyes, "visual-search"),
        "hand-object-tracker": _HandObject(eyes, "hand-object-tracker"),
        "change-detector": _Snapshots(eyes, "change-detector", eyes.change),
        "coplanar-detector": _Snapshots(eyes, "coplanar-detector", eyes.coplanar),
    }


# What each perception detector answers (lbw check validates rules against it).
VOCABULARY: dict[str, dict[str, frozenset]] = {
    "object-finder": {"methods": frozenset(_Objects.calls), "answers": frozenset()},
    "motion-detector": {"methods": frozenset(_Motion.calls), "answers": frozenset()},
    "hand-tracker": {"methods": frozenset(_Hand.calls), "answers": frozenset()},
    "visual-search": {"methods": frozenset(_Search.calls), "answers": frozenset()},
    "hand-object-tracker": {"methods": frozenset(_HandObject.calls), "answers": frozenset()},
    "change-detector": {"methods": frozenset(), "answers": frozenset(ChangeNode.answers)},
    "coplanar-detector": {"methods": frozenset(), "answers": frozenset(CoplanarNode.answers)},
}


def watch_frames(frames: Iterable[Frame], cameras: Mapping[str, Camera],
                 shapes: Mapping[str, Sequence[float]], rules: RuleSet,
                 names: Mapping[str, tuple[str, Sequence[float]]] | None = None
                 ) -> tuple[Recognizer, Eyes]:
    """Recognize a demonstration online from a frame source (images only)."""
    eyes = Eyes(cameras, shapes, rules, names)
    registry = DetectorRegistry.for_rules(rules, perception_detectors(eyes))
    recognizer = Recognizer(rules, registry)
    recognizer.run((f.t, f) for f in frames)
    return recognizer, eyes


__all__ = ["perception_detectors", "watch_frames"]
