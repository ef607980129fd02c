"""An oracle detector registry: what perfect detectors would answer, from the demonstrator's plan.

Evaluation only. The expected operation sequence of a demonstration is not
written in Python: the recognizer itself is run with the rules under test on a
registry of ideal detectors that answer every query from the demonstrator's
own schedule (perception.world.demonstrator) and the symbolic layouts of the
scenario, in the detectors' closed vocabulary (the method words of
rules/events.yaml, the change-detector's and coplanar-detector's answers).
Whatever the rules then make of those answers is what a perfect eye would
have recognized: rename an operation, add a Table V row, and the expected
sequence follows (issue #11).

A query's ``since`` (the frame its motion began on) says which demonstration
step it is about; the answers come at the schedule's boundaries:

| method          | answers when                                                     |
|-----------------|------------------------------------------------------------------|
| locate          | always: the teach objects, their true boxes and names            |
| moving-target   | the hand has entered the workspace                               |
| motion-feature  | the hand's planned velocity (the engine makes the Table IV value) |
| visual-search   | a step's transfer is over: its object, or where it is put        |
| contact         | the step's fine motion has begun                                 |
| separation      | the step's fine motion is over                                   |
| away            | the step's depart is over                                        |
| lost            | the hand has left at the end                                     |
"""

from __future__ import annotations

import math
from typing import Any

from lbw_engine.model.env import EnvModel
from lbw_engine.names import HAND
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import ActView, Detection, DetectorRegistry, ObjectInfo, Query
from lbw_engine.see.recognizer import Recognizer
from perception.vision.vfd.change import APPEARED, DISAPPEARED, NO_CHANGE
from perception.world.demonstrator import Demonstration, Segment
from perception.world.layout import slides

DT = 1e-3  # s: the finite difference of the planned path that gives the hand's velocity


class _Steps:
    """The demonstrator's schedule by step: transfer, fine motions, depart, their times."""

    def __init__(self, scenario: Any, demo: Demonstration, slide: float = 0.0) -> None:
        """Index the schedule of ``demo`` (a Demonstration of ``scenario``); ``slide`` is the
        least slide that is an align (rules/constants.yaml ``align-slide``)."""
        self.sc, self.demo, self.slide = scenario, demo, slide
        self.segments: dict[int, list[Segment]] = {}
        for seg in demo.segments:
            self.segments.setdefault(seg.step, []).append(seg)
        self.entered = next(s.t0 for s in demo.segments if s.phase != "absent")
        self.left = demo.segments[-1].t0  # the closing "absent" segment

    def step_at(self, t: float) -> int | None:
        """The step whose local motion (arrival above the target to the depart's end) holds t."""
        for i in range(len(self.sc.demonstration)):
            segs = self.segments[i]
            arrived = next(s.t1 for s in segs if s.phase == "transfer")
            if arrived - 1e-9 <= t <= segs[-1].t1 + 1e-9:
                return i
        return None

    def arrived(self, i: int) -> float:
        """When the hand arrived above step i's target (the transfer's end)."""
        return next(s.t1 for s in self.segments[i] if s.phase == "transfer")

    def fine(self, i: int) -> tuple[float, float]:
        """Start and end of step i's fine motions (grasp, release, touch, align slide)."""
        fine = [s for s in self.segments[i] if s.phase == "fine"]
        return fine[0].t0, fine[-1].t1

    def departed(self, i: int) -> float:
        """When step i's depart ended."""
        return self.segments[i][-1].t1


class OracleNode:
    """One ideal detector; ``calls`` maps the method words it answers to its functions."""

    calls: dict[str, str] = {}
    answers: tuple[Any, ...] = ()

    def __init__(self, steps: _Steps, name: str) -> None:
        """Answer from ``steps`` as detector ``name``."""
        self.steps, self.name = steps, name
        self.methods = frozenset(self.calls)
        self.t = 0.0
        self._entered = False

    def begin_frame(self, t: float, frame: Any) -> None:
        """The time of the current frame."""
        self.t = t

    def query(self, query: Query, env: EnvModel) -> Detection | None:
        """Answer by the method the rules' event-table names."""
        method = self.calls.get(query.method)
        return None if method is None else getattr(self, method)(query)

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """A snapshot is its time."""
        return act.t

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """Nothing to compare."""
        return None

    def hand(self, **kw: Any) -> Detection:
        """A detection with the hand's planned position."""
        return Detection(positions={HAND: self.steps.demo.planned(self.t)}, **kw)


class _World(OracleNode):
    calls = {"locate": "locate", "moving-target": "moving_target", "lost": "lost"}

    def locate(self, query: Query) -> Detection | None:
        """The teach objects where they are (true boxes, teach names)."""
        lay = self.steps.sc.teach.layout()
        objects = {n: ObjectInfo(self.steps.sc.teach.objects[n].shape, lay.size[n], c)
                   for n, c in lay.center.items()}
        return Detection(found=tuple(objects), objects=objects)

    def moving_target(self, query: Query) -> Detection | None:
        """The hand has entered the workspace (reported once, as the motion-detector does)."""
        if self.t < self.steps.entered or self._entered:
            return None
        self._entered = True
        return self.hand(found=(HAND,), t=self.steps.entered)

    def lost(self, query: Query) -> Detection | None:
        """The hand has left the workspace at the end."""
        return Detection(t=self.steps.left) if self.t >= self.steps.left else None


class _Hand(OracleNode):
    calls = {"motion-feature": "motion_feature", "away": "away", "visual-search": "search",
             "contact": "contact", "separation": "separation"}

    def motion_feature(self, query: Query) -> Detection | None:
        """The planned velocity of the hand (tremor-free)."""
        p0 = self.steps.demo.planned(max(0.0, self.t - DT))
        p1 = self.steps.demo.planned(self.t)
        return self.hand(velocity=tuple((b - a) / DT for a, b in zip(p0, p1, strict=True)))

    def search(self, query: Query) -> Detection | None:
        """Step i's target once its transfer is over: the object, or where it is put."""
        i = self.steps.step_at(self.t)
        if i is None or query.since >= self.steps.arrived(i):
            return None
        step = self.steps.sc.demonstration[i]
        found = tuple(step.on) if step.kind == "place" else (step.obj,)
        return self.hand(found=found, t=self.steps.arrived(i))

    def _after(self, query: Query, when: float) -> bool:
        """Whether the query's motion began before ``when`` and ``when`` has passed."""
        return query.since <= when + 1e-9 <= self.t + 1e-9

    def contact(self, query: Query) -> Detection | None:
        """The step's fine motion has begun."""
        i = self.steps.step_at(query.since)
        if i is None or not self._after(query, self.steps.fine(i)[0]):
            return None
        return self.hand(t=self.steps.fine(i)[0])

    def separation(self, query: Query) -> Detection | None:
        """The step's fine motion is over."""
        i = self.steps.step_at(query.since)
        if i is None or not self._after(query, self.steps.fine(i)[1]):
            return None
        return self.hand(t=self.steps.fine(i)[1])

    def away(self, query: Query) -> Detection | None:
        """The step's depart is over (dated at its end)."""
        i = self.steps.step_at(query.since)
        if i is None or not self._after(query, self.steps.departed(i)):
            return None
        return self.hand(t=self.steps.departed(i))


class _Change(OracleNode):
    answers = (APPEARED, DISAPPEARED, NO_CHANGE)

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """What a step's fine motion changed: a pick took the object, a place put it."""
        i = self.steps.step_at(act.since)
        if i is None or not first <= self.steps.fine(i)[0] <= last:
            return Detection(value=NO_CHANGE)
        step = self.steps.sc.demonstration[i]
        lay = self.steps.sc.states[i]
        if step.kind == "pick":
            before = self.steps.sc.states[i - 1] if i else self.steps.sc.teach.layout()
            return Detection(value=DISAPPEARED, position=before.center[step.obj])
        if step.kind == "place":
            return Detection(value=APPEARED, position=lay.center[step.obj])
        return Detection(value=NO_CHANGE)


class _Coplanar(OracleNode):
    answers = (1, 0, -1)

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """1 when the step's fine motion slid its object into line with another (ALIGN)."""
        i = self.steps.step_at(act.since)
        step = self.steps.sc.demonstration[i] if i is not None else None
        if step is None or not slides(step, self.steps.slide) \
                or not first <= self.steps.fine(i)[1] <= last:
            return Detection(value=0)
        return Detection(value=1, found=(step.align.with_,))


ORACLES = {"object-finder": _World, "motion-detector": _World, "hand-tracker": _Hand,
           "visual-search": _Hand, "hand-object-tracker": _Hand, "change-detector": _Change,
           "coplanar-detector": _Coplanar}


def oracle_recognizer(scenario: Any, rules: RuleSet, demo: Demonstration | None = None,
                      fps: float = 30.0, slide: float | None = None) -> Recognizer:
    """The recognizer run with ``rules`` on the oracle registry over the demonstration;
    ``slide``: the least slide that is an align (default: rules ``align-slide``)."""
    demo = demo or Demonstration(scenario, fps=fps)
    least = float(rules.constants["align-slide"]) if slide is None else slide
    steps = _Steps(scenario, demo, least)
    provided = {name: cls(steps, name) for name, cls in ORACLES.items()}
    recognizer = Recognizer(rules, DetectorRegistry.for_rules(rules, provided))
    n = int(math.floor(demo.duration * fps)) + 1
    recognizer.run((k / fps, None) for k in range(n))
    return recognizer
