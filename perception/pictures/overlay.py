"""The monitor display of Fig. 19, and videos of a demonstration and of an execution.

``draw_monitor`` draws one frame as the paper's monitor shows it: the top and
side views side by side with the live attention windows (yellow), the
hand-tracker's windows (green), and under them the attention stack (Sec. V-A,
one line per level) and the operation being recognized. ``record_demonstration``
draws it from ``watch_frames``'s per-frame hook, called after the recognizer has
finished each frame (so the picture shows what the recognizer knew at that
frame: online, no look-ahead), streams the monitor frames into an H.264 MP4 and keeps
a few for report.html;
``ExecutionRecorder`` is an ``on_step`` hook for ``execute_plan`` that renders
the robot's work through the same cameras.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from lbw_engine.rules import RuleSet
from lbw_engine.see.recognizer import Recognizer
from perception.pictures.video import VideoFile
from perception.vision.camera import default_cameras
from perception.vision.envnodes.hand import HandState
from perception.vision.envnodes.registry import watch_frames
from perception.vision.frames import Frame
from perception.world.render import Renderer

PANEL_H = 120  # px of text under the views
HAND_COLOR, ATTN_COLOR, TEXT_COLOR = (60, 220, 60), (0, 215, 255), (235, 235, 235)
FONT = cv2.FONT_HERSHEY_SIMPLEX
PANEL_GRAY, HEAD_ORG, HEAD_SCALE, HEAD_COLOR = 25, (8, 20), 0.55, (120, 230, 255)  # panel line 1

Window = tuple[str, tuple[int, int, int, int], str]  # (view, (x0, y0, x1, y1), kind)
FrameHook = Callable[[Frame, Recognizer, HandState], None]


def clock(t: float) -> str:
    """The time as the panel's first line starts with it (report.html's strips read it)."""
    return f"t = {t:6.2f} s"


def draw_monitor(top: np.ndarray, side: np.ndarray, windows: Sequence[Window],
                 stack_lines: Sequence[str], operation: str, t: float | None = None,
                 scale: int = 2) -> np.ndarray:
    """Both views (scaled) with window rectangles, and a text panel below (BGR image)."""
    views = {"top": top, "side": side}
    tiles = []
    for name in ("top", "side"):
        img = cv2.cvtColor(views[name], cv2.COLOR_GRAY2BGR) if views[name].ndim == 2 \
            else views[name].copy()
        img = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
        for view, (x0, y0, x1, y1), kind in windows:
            if view == name:
                color = HAND_COLOR if kind == "hand" else ATTN_COLOR
                cv2.rectangle(img, (x0 * scale, y0 * scale), (x1 * scale - 1, y1 * scale - 1),
                              color, 1)
        cv2.putText(img, name, (6, 18), FONT, 0.5, TEXT_COLOR, 1, cv2.LINE_AA)
        tiles.append(img)
    views_img = np.hstack([tiles[0], np.full((tiles[0].shape[0], 4, 3), 90, np.uint8), tiles[1]])
    panel = np.full((PANEL_H, views_img.shape[1], 3), PANEL_GRAY, np.uint8)
    head = f"{clock(t)}   " if t is not None else ""
    cv2.putText(panel, f"{head}operation: {operation}", HEAD_ORG, FONT, HEAD_SCALE, HEAD_COLOR,
                1, cv2.LINE_AA)
    lines = list(stack_lines)[-5:] or ["(attention stack empty)"]
    for k, line in enumerate(lines):
        cv2.putText(panel, line[:150], (8, 44 + 18 * k), FONT, 0.45, TEXT_COLOR, 1, cv2.LINE_AA)
    return np.vstack([views_img, panel])


def monitor_state(recognizer: Recognizer, hand: HandState
                  ) -> tuple[list[Window], list[str], str]:
    """What the monitor shows now: windows, attention stack lines, current operation."""
    hand_ids = {w.wid for ws in hand.tracker.windows.values() for w in ws}
    # VisionResources keeps no public list of live windows; the monitor only reads it.
    live = list(getattr(hand.sight.resources, "_live", {}).values())
    windows = [(w.view, (w.x0, w.y0, w.x1, w.y1), "hand" if w.wid in hand_ids else "attention")
               for w in live if w.wid not in hand_ids or hand.tracker.tracking]
    lines = []
    for level, nodes in enumerate(recognizer.stack.describe()):
        items = [f":{ev} {'/'.join(base) or '-'}>{'/'.join(target) or '-'}"
                 for ev, base, target in nodes]
        lines.append(f"ATTN level {level}: " + ("  ".join(items) or "-"))
    chain, node = [], recognizer.root
    while node is not None:
        chain.append(node.motion + (f"={node.operation}" if node.operation else ""))
        node = node.subnode
    last = recognizer.root.history[-1].operation if recognizer.root is not None and \
        recognizer.root.history else None
    operation = " > ".join(chain) or "-"
    if last:
        operation += f"   (last: {last})"
    return windows, lines, operation


def record_demonstration(scenario: Any, rules: RuleSet, video: str | Path | None = None,
                         keep_every: float = 2.0, fps: float = 30.0, scale: int = 2,
                         on_frame: FrameHook | None = None
                         ) -> tuple[Recognizer, HandState, list[tuple[float, np.ndarray]]]:
    """Watch ``scenario`` on the monitor; MP4 to ``video``; keep one frame per ``keep_every`` s.

    ``on_frame`` is a further per-frame hook (e.g. ``motiontrace.MotionRecorder``), called
    after the monitor is drawn, with the same arguments as ``watch_frames``'s.
    """
    from perception.world.stream import demonstration_frames, teach_names

    cameras = default_cameras()
    out = VideoFile(video, fps)
    kept: list[tuple[float, np.ndarray]] = []

    def monitor(frame: Frame, rec: Recognizer, hand: HandState) -> None:
        """Draw the monitor; stream it, keep a sample."""
        wins, lines, op = monitor_state(rec, hand)
        image = draw_monitor(frame.top, frame.side, wins, lines, op, frame.t, scale)
        out.add(image)
        if not kept or frame.t - kept[-1][0] >= keep_every - 1e-9:
            kept.append((frame.t, image))
        if on_frame is not None:
            on_frame(frame, rec, hand)

    try:
        rec, hand = watch_frames(demonstration_frames(scenario, cameras, fps=fps), cameras,
                                 scenario.shapes, rules, teach_names(scenario), monitor)
    finally:
        out.close()
    return rec, hand, kept


class ExecutionRecorder:
    """``on_step`` hook for ``execute_plan``: renders the robot's world ``fps`` times per
    second of robot time, so the video plays in real time whatever the robot's step."""

    def __init__(self, video: str | Path | None = None, fps: float = 30.0,
                 keep_every: float = 2.0, pixel_noise: float = 2.0, scale: int = 2) -> None:
        """Record to ``video`` (MP4) and keep a frame every ``keep_every`` s of robot time."""
        self.renderer = Renderer(default_cameras(), pixel_noise=pixel_noise, seed=0)
        self.out = VideoFile(video, fps)
        self.period, self.keep_every, self.scale = 1.0 / fps, keep_every, scale
        self.steps = 0  # robot steps seen
        self.rendered = 0  # frames drawn (one per period)
        self.next_t: float | None = None
        self.kept: list[tuple[float, np.ndarray]] = []
        self.monitor: Any = None

    def follow(self, monitor: Any, robot: Any, eyes: Any) -> None:
        """Show the execution monitor (issue #13): the ACHIEVE and command under way, the
        blocks of the monitor's last look as windows, its detections and repairs."""
        self.monitor, self.robot, self.eyes = monitor, robot, eyes

    def _panel(self) -> tuple[str, list[str], list]:
        """(operation line, panel lines, windows) of the monitor's state now."""
        mon = self.monitor
        if mon is None:
            return "execution", ["robot executing the plan"], []
        cmd = self.robot.current.text() if self.robot.current is not None else "-"
        lines = [f"detected: {d['object']} ({d.get('kind', '?')}) after {d['operator']}, "
                 f"expected {_say(d['expected'])}, seen {_say(d['observed'])}"
                 for d in mon.detections]
        lines += [f"repair: {r['operator']} again, {r['commands']} commands"
                  for r in mon.repairs]
        return (f"{mon.current or '-'}: {cmd}", lines[-4:] or ["monitor: as expected"],
                self.eyes.windows)

    def __call__(self, world: Any) -> None:
        """Render the world when a period has passed (read only through its scene)."""
        self.steps += 1
        if self.next_t is not None and world.time < self.next_t - 1e-9:
            return
        self.next_t = (world.time if self.next_t is None else self.next_t) + self.period
        watch = getattr(self.monitor, "watch", None)  # the monitor's eyes on the robot
        views = watch.render(world) if watch is not None else self.renderer.render(world.scene())
        operation, lines, windows = self._panel()
        image = draw_monitor(views["top"], views["side"], windows, lines, operation,
                             world.time, self.scale)
        self.out.add(image)
        self.rendered += 1
        if not self.kept or world.time - self.kept[-1][0] >= self.keep_every - 1e-9:
            self.kept.append((world.time, image))

    def close(self) -> None:
        """Finish the video file."""
        self.out.close()


def _say(value: Any) -> str:
    """A detection's expected or observed value for the panel: numbers in whole mm (a
    list's numpy floats printed as np.float64(29.2): helper round 21)."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_say(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:.0f}"
    return str(value)
