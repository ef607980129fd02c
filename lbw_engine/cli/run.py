"""``lbw run SCENARIO [--out DIR] [--rules DIR]``: see, understand and do, end to end.

watch (demonstrator → cameras → detectors → recognizer, Sec. III–V) →
analyze (templates, state changes, dependency closures, Sec. VI) →
execute (matching, Table IX commands, robot, verification, Sec. VII), through
lbw_engine.pipeline.run. Writes actions.json, plan.json, plan.txt,
commands.txt and execution.json. Exit 0 only when the recognized sequence is
the demonstrated one and the execution verified (or, for a scenario without an
``execute`` workspace, a plan was learned); 1 when a phase failed or did not
verify (``failure`` in execution.json starts with the first phase that went
wrong); 2 on bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.execute import fault_notes
from lbw_engine.pipeline.run import publish, repair_lines, verdict_words
from lbw_engine.pipeline.run import run as run_pipeline
from lbw_engine.pipeline.watch import slide_notes

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
            result = run_pipeline(scenario, args.rules)
        publish(result, out)
    rec = result.recognition
    print(f"lbw run: {scenario.name}: {len(rec['recognized'])} operations recognized "
          f"({verdict_words(rec)}); outputs in {args.out}")
    for line in repair_lines(result.actions):
        print(f"lbw run: {line}")
    for line in slide_notes(scenario, result.rules) + fault_notes(
            result.execution.report if result.execution else {}):
        print(f"lbw run: {line}", file=sys.stderr)
    if not result.success:
        print(f"lbw run: failed: {result.failure}", file=sys.stderr)
        return 1
    print(f"lbw run: success ({result.execution.message if result.execution else 'plan learned'})")
    return 0
