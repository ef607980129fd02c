"""Pictures of a run for ``lbw run --video / --report`` (issue #7); not a subcommand.

``run_with_pictures`` is ``pipeline.run`` with eyes for people: the
demonstration is watched through the monitor display of Fig. 19
(``perception.pictures.overlay``), the robot's execution is rendered through the same
cameras, the plan is drawn (``perception.pictures.plandraw``) and everything is put into
one self-contained ``report.html`` (``perception.pictures.report``). Files staged into
the caller's OutputDir:

| flag     | files                                                               |
|----------|---------------------------------------------------------------------|
| video    | demonstration.mp4, execution.mp4 (both views side by side, overlays) |
| report   | report.html (frames embedded as data URIs)                          |
| either   | plan.svg, plan.png                                                  |

The caller still publishes the usual files (``pipeline.run.publish``). Recognition is
the same as ``lbw watch`` (the monitor only reads the recognizer after each
frame; tests/report/test_overlay.py checks the sequences are identical).
"""

from __future__ import annotations

from typing import Any

from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.run import RunResult
from lbw_engine.pipeline.run import run as pipeline


def run_with_pictures(scenario: Any, rules_dir: Any, out: OutputDir, video: bool = True,
                      report: bool = True, fps: float = 30.0) -> RunResult:
    """``pipeline`` with the monitor as watcher and the robot recorded; stage the pictures."""
    from perception.pictures.overlay import ExecutionRecorder, record_demonstration
    from perception.pictures.plandraw import png_bytes, svg_text
    from perception.pictures.report import run_report

    kept: list = []

    def watcher(sc: Any, rules: Any, rate: float) -> Any:
        """Watch through the monitor display (Fig. 19), streaming the MP4."""
        rec, _, frames = record_demonstration(
            sc, rules, out.path("demonstration.mp4") if video else None, fps=rate)
        kept.extend(frames)
        return rec

    recorder = ExecutionRecorder(out.path("execution.mp4") if video else None, fps=fps,
                                 pixel_noise=scenario.noise.pixel)
    try:
        result = pipeline(scenario, rules_dir, fps=fps, watcher=watcher, on_step=recorder)
    finally:
        recorder.close()
    if result.plan is not None:
        out.write_text("plan.svg", svg_text(result.plan))
        out.path("plan.png").write_bytes(png_bytes(result.plan))
    if report:  # the robot's frames follow the demonstration's on the report's time axis
        end = kept[-1][0] if kept else 0.0
        frames = kept + [(end + 1.0 + t, img) for t, img in recorder.kept]
        out.write_text("report.html", run_report(scenario, result.rules, result.actions,
                                                 result.plan, result.plan_text,
                                                 result.execution, frames=frames))
    return result
