"""The image-backed detector registry: one ENV-node per detector of rules/events.yaml.

| detector            | methods (its vocabulary)         | VFDs (docs/vision.md)        |
|---------------------|----------------------------------|------------------------------|
| object-finder       | locate                           | ObjectFinder                 |
| motion-detector     | moving-target                    | MotionDetector, HandTracker  |
| hand-tracker        | lost, motion-feature, away       | HandTracker                  |
| visual-search       | visual-search                    | SilFinder                    |
| hand-object-tracker | contact, separation              | HandTracker                  |
| change-detector     | snapshots: appeared/vanished/nochange | ChangeDetector          |
| coplanar-detector   | snapshots: 1 / 0 / -1            | CoplanarDetector             |

The nodes share only the tracked hand (``HandState``); ``watch_frames`` wires
them into a ``Recognizer`` and runs it online over a frame source.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import DetectorRegistry
from lbw_engine.see.recognizer import Recognizer
from perception.vision.camera import Camera
from perception.vision.envnodes.change import ChangeNode
from perception.vision.envnodes.coplanar import CoplanarNode
from perception.vision.envnodes.hand import HandState, Sight
from perception.vision.envnodes.objects import ObjectFinderNode
from perception.vision.envnodes.search import SearchNode
from perception.vision.envnodes.tracker import ContactNode, HandTrackerNode, MotionNode
from perception.vision.frames import Frame

NODES = (ObjectFinderNode, MotionNode, HandTrackerNode, SearchNode, ContactNode, ChangeNode,
         CoplanarNode)

# What each perception detector answers (lbw check validates rules against it).
VOCABULARY: dict[str, dict[str, frozenset]] = {
    node.name: {"methods": frozenset(node.calls), "answers": frozenset(node.answers)}
    for node in NODES
}


def perception_detectors(hand: HandState, rules: RuleSet, shapes: Mapping[str, Sequence[float]],
                         names: Mapping[str, tuple[str, Sequence[float]]] | None = None,
                         located: Mapping[str, tuple[str, Sequence[float]]] | None = None
                         ) -> dict[str, Any]:
    """Detector name (rules/events.yaml) -> image-backed ENV-node."""
    out: dict[str, Any] = {}
    for node in NODES:
        extra = {"shapes": shapes, "names": names, "located": located} \
            if node is ObjectFinderNode else {}
        out[node.name] = node(hand, rules, **extra)
    return out


def new_recognizer(cameras: Mapping[str, Camera], shapes: Mapping[str, Sequence[float]],
                   rules: RuleSet, names: Mapping[str, tuple[str, Sequence[float]]] | None = None,
                   located: Mapping[str, tuple[str, Sequence[float]]] | None = None
                   ) -> tuple[Recognizer, HandState]:
    """A recognizer wired to fresh image-backed ENV-nodes, to be fed frames with ``step``
    (``watch_frames`` does; so does the robot's execution monitor, one per ACHIEVE, with
    ``located``: its last look, see ObjectFinderNode)."""
    hand = HandState(Sight(cameras), rules)
    registry = DetectorRegistry.for_rules(
        rules, perception_detectors(hand, rules, shapes, names, located))
    return Recognizer(rules, registry), hand


def watch_frames(frames: Iterable[Frame], cameras: Mapping[str, Camera],
                 shapes: Mapping[str, Sequence[float]], rules: RuleSet,
                 names: Mapping[str, tuple[str, Sequence[float]]] | None = None,
                 on_frame: Callable[[Frame, Recognizer, HandState], None] | None = None
                 ) -> tuple[Recognizer, HandState]:
    """Recognize a demonstration online from a frame source (images only).

    ``on_frame(frame, recognizer, hand)`` runs after each frame's steps (the monitor
    display). Returns the recognizer and the tracked hand (its ``sight`` counts the
    pixels read).
    """
    recognizer, hand = new_recognizer(cameras, shapes, rules, names)
    for frame in frames:
        if recognizer.finished:
            break
        recognizer.step(frame.t, frame)
        if on_frame is not None:
            on_frame(frame, recognizer, hand)
    recognizer.finish()
    return recognizer, hand


__all__ = ["NODES", "VOCABULARY", "new_recognizer", "perception_detectors", "watch_frames"]
