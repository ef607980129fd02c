"""The hand's motion features over a watch, recorded for the report's motion plot.

The recognizer turns the tracked hand's 3-D velocity into Table IV values
(speed against V_L/V_H of a range, direction against A_D/A_U, footnote 11) and
cuts the motion where Table VII says an event ends one ACT-node and starts the
next. ``MotionRecorder`` is a per-frame hook for ``watch_frames`` (through
``overlay.record_demonstration``) that keeps what a reader needs to see why:

- per frame, while the hand-tracker answers ``motion-feature`` queries (tracking
  and steady, as ``HandTrackerNode.motion_feature`` requires): the speed, the
  angle from straight down and the height of the hand;
- at the end, the recognizer's event log (t, motion, event, value) and every
  ACT-node's interval with the events that opened and closed it (Fig. 12).

It only reads the recognizer and the tracked hand after each frame, so it does
not change recognition (tests/report/test_overlay.py checks that).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lbw_engine.see.motionfeatures import down_angle


@dataclass(frozen=True)
class MotionSample:
    """One frame of the tracked hand: time (s), speed (mm/s), angle from down (deg), z (mm)."""

    t: float
    speed: float
    angle: float | None
    z: float


@dataclass(frozen=True)
class LoggedEvent:
    """One event the recognizer interpreted (``Recognizer.log``)."""

    t: float
    motion: str
    event: str
    value: str | None


@dataclass(frozen=True)
class Segment:
    """One ACT-node's interval: where the motion was cut, and by which events."""

    level: int
    name: str
    motion: str
    operation: str | None
    t_start: float
    t_end: float
    initial_event: str | None
    final_event: str | None


@dataclass
class MotionTrace:
    """Everything the motion plot draws, for one watched demonstration."""

    samples: list[MotionSample] = field(default_factory=list)
    events: list[LoggedEvent] = field(default_factory=list)
    segments: list[Segment] = field(default_factory=list)
    t_end: float = 0.0


class MotionRecorder:
    """``on_frame`` hook: records the hand's motion features frame by frame."""

    def __init__(self) -> None:
        """An empty trace; ``finish`` adds the recognizer's events and segments."""
        self.trace = MotionTrace()

    def __call__(self, frame: Any, recognizer: Any, hand: Any) -> None:
        """Keep this frame's sample when the hand-tracker would answer a feature query."""
        self.trace.t_end = float(frame.t)
        if not (hand.tracking and hand.steady):
            return
        velocity = np.asarray(hand.velocity, float)
        self.trace.samples.append(MotionSample(float(frame.t), float(np.linalg.norm(velocity)),
                                               down_angle(velocity), float(hand.hand[2])))

    def finish(self, recognizer: Any) -> MotionTrace:
        """Add the event log and the ACT-nodes' intervals once the watch has ended."""
        self.trace.events = [LoggedEvent(float(t), motion, event,
                                         None if value is None else str(value))
                             for t, motion, event, value in recognizer.log]
        self.trace.segments = segments(recognizer.root)
        return self.trace


def segments(root: Any) -> list[Segment]:
    """Every ended ACT-node under ``root``, depth first (levels as in the attention stack)."""
    out: list[Segment] = []
    stack = list(reversed(root.history)) if root is not None else []
    while stack:
        node = stack.pop()
        if node.t_end is not None:
            out.append(Segment(node.level, node.name, node.motion, node.operation,
                               float(node.t_start), float(node.t_end),
                               node.initial_event, node.final_event))
        stack.extend(reversed(node.history))
    return out
