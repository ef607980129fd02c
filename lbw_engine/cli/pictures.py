"""Pictures of a run for ``lbw run --video / --report`` (issue #7); not a subcommand.

``run_with_pictures`` is ``run.pipeline`` with eyes for people: the
demonstration is watched through the monitor display of Fig. 19
(``perception.overlay``), the robot's execution is rendered through the same
cameras, the plan is drawn (``perception.plandraw``) and everything is put into
one self-contained ``report.html`` (``perception.report``). Files staged into
the caller's OutputDir:

| flag     | files                                                               |
|----------|---------------------------------------------------------------------|
| video    | demonstration.mp4, execution.mp4 (both views side by side, overlays) |
| report   | report.html (frames embedded as data URIs)                          |
| either   | plan.svg, plan.png                                                  |

The caller still publishes the usual files (``run.publish``). Recognition is
the same as ``lbw watch`` (the monitor only reads the recognizer after each
frame; tests/report/test_overlay.py checks the sequences are identical).
"""

from __future__ import annotations

import time
from typing import Any

from ..actions import to_actions
from ..analysis import RelationTable, analyze, parse_actions, write_plan_text
from ..analysis import load_rules as load_analysis_rules
from ..errors import InputError
from ..execution import commandrules
from ..execution import plan as planmod
from ..outputs import OutputDir
from ..rules import load_rules
from .execute import execute_plan
from .run import RunResult, compare_with_truth


def run_with_pictures(scenario: Any, rules_dir: Any, out: OutputDir, video: bool = True,
                      report: bool = True, fps: float = 30.0) -> RunResult:
    """watch (monitored) → analyze → execute (recorded); stage videos, plan pictures, report."""
    from perception.overlay import ExecutionRecorder, record_demonstration
    from perception.plandraw import png_bytes, svg_text
    from perception.report import run_report

    rules = load_rules(rules_dir)
    arules = load_analysis_rules(rules.directory)
    crules = commandrules.load_dir(rules.directory)
    clock = time.perf_counter()
    rec, _, kept = record_demonstration(
        scenario, rules, out.path("demonstration.mp4") if video else None, fps=fps)
    actions = to_actions(rec)
    result = RunResult(scenario, actions, compare_with_truth(scenario, actions))
    result.seconds["watch"] = time.perf_counter() - clock
    recorder = ExecutionRecorder(out.path("execution.mp4") if video else None, fps=fps,
                                 pixel_noise=scenario.noise.pixel)
    try:
        seq = parse_actions(actions, RelationTable(arules.tolerance), file="actions.json")
        result.plan = analyze(seq, arules).plan
    except InputError as exc:
        result.failure = f"analysis: {exc}"
    if result.plan is not None:
        result.plan_text = write_plan_text(result.plan)
        out.write_text("plan.svg", svg_text(result.plan))
        out.path("plan.png").write_bytes(png_bytes(result.plan))
        if scenario.execute is not None:
            clock = time.perf_counter()
            plan = planmod.parse(result.plan, file="plan.json")
            try:
                result.execution = execute_plan(plan, scenario, crules, on_step=recorder)
            finally:
                recorder.close()
            result.seconds["execute"] = time.perf_counter() - clock
            if not result.execution.success:
                result.failure = f"execution: {result.execution.message}"
    recorder.close()
    if report:  # the robot's frames follow the demonstration's on the report's time axis
        end = kept[-1][0] if kept else 0.0
        frames = kept + [(end + 1.0 + t, img) for t, img in recorder.kept]
        out.write_text("report.html", run_report(scenario, actions, result.plan,
                                                 result.plan_text, result.execution,
                                                 frames=frames))
    return result
