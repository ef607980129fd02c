"""The robot watched by the demonstration's recognizer (Sec. IX-C2, issue #13 item 2).

The paper's proposal for failures: recognize the robot's operations with the
same action recognizer and compare them with the operations being executed.
``RobotWatch`` is the robot's per-step hook: it renders the execution world
through the same cameras and renderer as the demonstration, ``fps`` times per
second of robot time, and feeds the frames online, in order, to a recognizer
configured from the same rules and image-backed detectors as ``lbw watch``.
The detectors find the subject by its gray band; the gripper is drawn in
another band than the hand, so its frames go through the gripper's appearance
first (``perception.vision.vfd.subject``). The detectors read only those
images.

One recognizer per ACHIEVE: the monitor's look between ACHIEVEs takes the
gripper out of both views, which ends the recognizer's Task (the hand is lost
from the world, as when a demonstrator withdraws), so each ACHIEVE is watched
like a short demonstration whose initial state is the monitor's last look (the
same cameras, read against the plan's expected state: ObjectFinderNode
``located``). The execution video (``ExecutionRecorder``) draws the frames
rendered here instead of rendering its own.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from lbw_engine.rules import RuleSet

WATCH_FPS = 30.0  # frames per second of robot time, as the demonstration is watched
DROP_FRAMES = 3  # frames in a row that show the jaws empty while gripping: a drop


class RobotWatch:
    """Renders the execution and recognizes the gripper's operations, one ACHIEVE at a time."""

    def __init__(self, renderer: Any, shapes: Mapping[str, Sequence[float]], rules: RuleSet,
                 fps: float = WATCH_FPS) -> None:
        """``renderer`` draws the world's scene (the world is never read otherwise)."""
        from perception.vision.vfd.subject import SubjectView

        self.renderer, self.shapes, self.rules = renderer, shapes, rules
        self.subject = SubjectView("gripper")
        self.period = 1.0 / fps
        self.next_t: float | None = None
        self.index = 0
        self.views: dict[str, Any] | None = None  # the last rendered views and their time
        self.views_t: float | None = None
        self.rec: Any = None
        self.frames = 0  # frames recognized, all units
        # the carry watched too (``perception.vision.vfd.held``): set by the caller
        self.robot: Any = None  # its jaws' pose, width and own sense of gripping
        self.back: Any = None  # the third view's renderer (monitor.Eyes.back)
        self.drops: list[float] = []  # times a carried block was seen gone, this unit
        self._empty = 0

    def begin(self, located: Mapping[str, tuple[str, Sequence[float]]]) -> None:
        """Start watching a unit from the monitor's last look (name -> shape, centre)."""
        from perception.vision.envnodes.registry import new_recognizer

        self.rec, _ = new_recognizer(self.renderer.cameras, self.shapes, self.rules,
                                     located=located)
        self.drops, self._empty = [], 0

    def end(self) -> list[Any]:
        """Stop watching the unit: the recognized ACT-nodes of its Task, in order."""
        rec, self.rec = self.rec, None
        if rec is None:
            return []
        rec.finish()
        return list(rec.root.history) if rec.root is not None else []

    def __call__(self, world: Any) -> None:
        """One robot step: a frame when a period has passed and a unit is watched."""
        if self.next_t is not None and world.time < self.next_t - 1e-9:
            return
        self.next_t = (world.time if self.next_t is None else self.next_t) + self.period
        if self.rec is None or self.rec.finished:
            self.index += 1
            return
        from perception.vision.frames import Frame

        views = self.render(world)
        frame = self.subject.frame(Frame(self.index, world.time, views["top"], views["side"]))
        self.index += 1
        self.frames += 1
        self.rec.step(world.time, frame)
        self._carry(world, views)

    def _carry(self, world: Any, views: Mapping[str, Any]) -> None:
        """While the robot feels its jaws closed on a block, whether the views still show
        a block between them; DROP_FRAMES frames in a row without: it was dropped."""
        from perception.vision.vfd.held import jaw_space, jaws_empty
        from perception.world.robot import FINGERTIP

        robot = self.robot
        if robot is None or not robot.gripping:
            self._empty = 0
            return
        g = robot.gripper
        cams, images = dict(self.renderer.cameras), {"side": views["side"]}
        if self.back is not None:
            cams |= self.back.cameras
            images |= self.back.render(world.scene())
        own = [(b.center, b.size) for b in g.boxes()]
        empty = jaws_empty(cams, images, jaw_space(g.position, g.axis, g.opening, FINGERTIP),
                           own)
        if self._empty < DROP_FRAMES:  # one detection per carry
            self._empty = self._empty + 1 if empty else (0 if empty is False else self._empty)
            if self._empty == DROP_FRAMES:
                self.drops.append(round(world.time, 2))

    def render(self, world: Any) -> dict[str, Any]:
        """The views of the world now, rendered once per step (the video reuses them)."""
        if self.views_t != world.time or self.views is None:
            self.views, self.views_t = self.renderer.render(world.scene()), world.time
        return self.views
