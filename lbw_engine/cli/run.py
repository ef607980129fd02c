"""``lbw run SCENARIO [--out DIR] [--rules DIR]``: see, understand and do, end to end.

watch (demonstrator → cameras → detectors → recognizer, Sec. III–V) →
analyze (templates, state changes, dependency closures, Sec. VI) →
execute (matching, Table IX commands, robot, verification, Sec. VII).
Writes actions.json, plan.json, plan.txt, commands.txt and execution.json.
Exit 0 only when the recognized sequence is the demonstrated one and the
execution verified (or, for a scenario without an ``execute`` workspace, a plan
was learned); 1 when a phase failed or did not verify; 2 on bad input.
``pipeline()`` is the reusable core (demo, bench and report use it).

The ground truth is consulted only *after* recognition, to check the
recognized sequence against what the demonstrator did (evaluation).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lbw_engine.cli.watch import watch
from lbw_engine.do import plan as planmod
from lbw_engine.errors import InputError
from lbw_engine.outputs import OutputDir
from lbw_engine.rules import commands as commandrules
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.understand import RelationTable, analyze, parse_actions, write_plan_text
from lbw_engine.understand import load_rules as load_analysis_rules

HELP = "watch a demonstration, learn its plan, execute it in the new layout and verify"
EXIT_CODES = ("0 success; 1 the task failed: recognition differs from the demonstration, or "
              "execution did not verify (the files are still written, execution.json names the "
              "phase); 2 bad input (one line: file, place, what is wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """SCENARIO, --out, --rules."""
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    parser.add_argument("--out", metavar="DIR", default="out", help="output folder (out)")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")
    parser.add_argument("--video", action="store_true",
                        help="also write demonstration.mp4 and execution.mp4 (Fig. 19 monitor)")
    parser.add_argument("--report", action="store_true",
                        help="also write a self-contained report.html")


@dataclass
class RunResult:
    """Everything one end-to-end run produced, phase by phase."""

    scenario: Any
    actions: dict[str, Any]
    recognition: dict[str, Any]
    plan: dict[str, Any] | None = None
    plan_text: str | None = None
    execution: Any = None  # lbw_engine.cli.execute.ExecutionResult
    failure: str | None = None  # first phase that failed, with why
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def success(self) -> bool:
        """No phase failed: recognized as demonstrated (design.md: a recognition that does
        not verify fails the task), a plan learned, and any execution verified."""
        if self.failure or self.plan is None:
            return False
        return self.execution is None or bool(self.execution.success)

    def report(self) -> dict[str, Any]:
        """execution.json: the verdict of the whole run."""
        out: dict[str, Any] = {"success": self.success}
        if self.failure:
            out["failure"] = self.failure
        if self.execution is not None:
            out.update({k: v for k, v in self.execution.report.items() if k != "success"})
        out["recognition"] = self.recognition
        out["seconds"] = {k: round(v, 3) for k, v in self.seconds.items()}
        return out


def compare_with_truth(scenario: Any, actions: dict[str, Any]) -> dict[str, Any]:
    """The recognized top-level sequence against the ground truth (evaluation only)."""
    from lbw_engine.report.metrics import compare_sequence
    from perception.world.groundtruth import expected_operations

    expected = list(expected_operations(scenario))
    recognized = [op["operation"] for op in actions["operations"]]
    # The bench's definition (lbw_engine/report/metrics.py): a repeated closing
    # operation counts once (the hand leaving may be split, Fig. 12).
    same = compare_sequence([{"operation": op} for op in expected], actions["operations"])
    return {"expected": expected, "recognized": recognized, "exact": same["exact"],
            "difference": same["difference"]}


def pipeline(scenario: Any, rules_dir: str | Path | None = None, fps: float = 30.0,
             watcher: Callable[..., Any] | None = None,
             on_step: Callable[[Any], None] | None = None) -> RunResult:
    """Run watch → analyze → execute on a loaded scenario; never raises for a failed task.

    ``watcher(scenario, rules, fps)`` replaces the plain watch (it must return
    the recognizer), e.g. to draw the monitor display; ``on_step(world)`` is
    called after every step of the robot's world (to record the execution).
    """
    from lbw_engine.cli.execute import execute_plan

    rules = load_rules(rules_dir)
    arules = load_analysis_rules(rules.directory)
    crules = commandrules.load_dir(rules.directory)
    clock = time.perf_counter()
    if watcher is None:
        recognizer, _ = watch(scenario, rules, fps=fps)
    else:
        recognizer = watcher(scenario, rules, fps)
    actions = to_actions(recognizer)
    result = RunResult(scenario, actions, compare_with_truth(scenario, actions))
    result.seconds["watch"] = time.perf_counter() - clock
    clock = time.perf_counter()
    try:  # the recognizer's own output: a template mismatch is a failed task, not bad input
        seq = parse_actions(actions, RelationTable(arules.tolerance), file="actions.json")
        analysis = analyze(seq, arules)
    except InputError as exc:
        result.failure = f"analysis: {exc}"
        return result
    result.plan = analysis.plan
    result.plan_text = write_plan_text(analysis.plan)
    result.seconds["analyze"] = time.perf_counter() - clock
    if scenario.execute is not None:
        clock = time.perf_counter()
        plan = planmod.parse(analysis.plan, file="plan.json")
        result.execution = execute_plan(plan, scenario, crules, on_step=on_step)
        result.seconds["execute"] = time.perf_counter() - clock
        if not result.execution.success:
            result.failure = f"execution: {result.execution.message}"
    if result.failure is None and not result.recognition["exact"]:
        # Every phase ran (their files are written), but what was learned is not what
        # was shown: the task failed (design.md exit codes).
        result.failure = f"recognition: {result.recognition['difference']}"
    return result


def publish(result: RunResult, out: OutputDir) -> None:
    """Stage the run's files (design.md: actions, plan, plan text, commands, verdict)."""
    out.write_json("actions.json", result.actions)
    if result.plan is not None:
        out.write_json("plan.json", result.plan)
        out.write_text("plan.txt", result.plan_text or "")
    if result.execution is not None:
        out.write_text("commands.txt", result.execution.commands_text)
    out.write_json("execution.json", result.report())


def run(args: argparse.Namespace) -> int:
    """Run the pipeline, publish every file, exit 0 only on success."""
    from perception.world.scenario import load

    scenario = load(Path(args.scenario))
    inputs = [args.scenario, *([args.rules] if args.rules else [])]
    with OutputDir(args.out, inputs=inputs) as out:
        if args.video or args.report:
            from lbw_engine.cli.pictures import run_with_pictures

            result = run_with_pictures(scenario, args.rules, out, video=args.video,
                                       report=args.report)
        else:
            result = pipeline(scenario, args.rules)
        publish(result, out)
    rec = result.recognition
    print(f"lbw run: {scenario.name}: {len(rec['recognized'])} operations recognized "
          f"({'exactly as demonstrated' if rec['exact'] else 'NOT as demonstrated'}); "
          f"outputs in {args.out}")
    if not result.success:
        print(f"lbw run: failed: {result.failure or 'no plan'}", file=sys.stderr)
        return 1
    print(f"lbw run: success ({result.execution.message if result.execution else 'plan learned'})")
    return 0
