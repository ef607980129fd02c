"""Pictures of a run for ``lbw run --video / --report`` (issue #7, #14); not a subcommand.

``run_with_pictures`` is ``pipeline.run`` with eyes for people: the
demonstration is watched through the monitor display of Fig. 19
(``perception.pictures.overlay``) while the hand's motion features are recorded
(``perception.pictures.motiontrace``), the robot's execution is rendered through
the same cameras, the plan is drawn (``perception.pictures.plandraw``) and
everything is put into one self-contained ``report.html``
(``perception.pictures.report``). Files staged into the caller's OutputDir:

| flag     | files                                                                      |
|----------|----------------------------------------------------------------------------|
| video    | demonstration.mp4, execution.mp4 (H.264; both views side by side, overlays) |
| report   | report.html (videos, frames and pictures embedded as data URIs)            |
| either   | plan.svg, plan.png                                                         |

With ``--report`` alone the videos are still made, in a temporary folder, to be
embedded. The caller still publishes the usual files (``pipeline.run.publish``).
Recognition is the same as ``lbw watch`` (the monitor and the motion recorder
only read the recognizer after each frame; tests/report/ checks the sequences
are identical).
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.run import RunResult
from lbw_engine.pipeline.run import run as pipeline

VIDEOS = ("demonstration", "execution")


def run_with_pictures(scenario: Any, rules_dir: Any, out: OutputDir, video: bool = True,
                      report: bool = True, fps: float = 30.0, scale: int = 2) -> RunResult:
    """``pipeline`` with the monitor as watcher and the robot recorded; stage the pictures.

    ``scale`` enlarges the 256-pixel camera images in the videos and frames.
    """
    with tempfile.TemporaryDirectory(prefix="lbw-videos-") as scratch:
        files = video_files(out, Path(scratch), video, report)
        return _run(scenario, rules_dir, out, files, report, fps, scale)


def video_files(out: OutputDir, scratch: Path, video: bool, report: bool) -> dict[str, Path]:
    """Where each video is written: staged for publishing with ``video``, else in
    ``scratch`` when only the report needs them, else nowhere (not recorded)."""
    if video:
        return {v: out.path(f"{v}.mp4") for v in VIDEOS}
    return {v: scratch / f"{v}.mp4" for v in VIDEOS} if report else {}


def _run(scenario: Any, rules_dir: Any, out: OutputDir, files: dict[str, Path], report: bool,
         fps: float, scale: int) -> RunResult:
    """Watch, analyze and execute with recorders; stage plan pictures and report.html."""
    from perception.pictures.motiontrace import MotionRecorder
    from perception.pictures.overlay import ExecutionRecorder, record_demonstration
    from perception.pictures.plandraw import png_bytes, svg_text
    from perception.pictures.report import run_report

    kept: list = []
    motion = MotionRecorder()
    traces: list = []

    def watcher(sc: Any, rules: Any, rate: float) -> Any:
        """Watch through the monitor display (Fig. 19), streaming the MP4."""
        rec, _, frames = record_demonstration(sc, rules, files.get("demonstration"), fps=rate,
                                              scale=scale, keep_every=1.0, on_frame=motion)
        kept.extend(frames)
        traces.append(motion.finish(rec))
        return rec

    recorder = ExecutionRecorder(files.get("execution"), fps=fps, keep_every=1.0,
                                 pixel_noise=scenario.noise.pixel, scale=scale)
    try:
        result = pipeline(scenario, rules_dir, fps=fps, watcher=watcher, on_step=recorder)
    finally:
        recorder.close()
    if result.plan is not None:
        out.write_text("plan.svg", svg_text(result.plan))
        out.path("plan.png").write_bytes(png_bytes(result.plan))
    if report:
        out.write_text("report.html", run_report(
            scenario, result.rules, result.actions, result.plan, result.plan_text,
            result.execution, frames=kept, execution_frames=recorder.kept, videos=files,
            trace=traces[0] if traces else None, execution_json=result.report()))
    return result
