"""``lbw demo``: the bundled Build-Table task (Sec. VIII) end to end.

Watches the demonstration through the two cameras, learns the plan, executes
it in the execution workspace and prints what the paper's figures show: the
recognized sequence (Fig. 20), the top two levels of the plan (Fig. 22), the
number of manipulator commands (Sec. VIII: 45) and the verdict.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from lbw_engine.outputs import OutputDir
from lbw_engine.paths import bundled_scenario

HELP = "run the bundled Build-Table task end to end and show the result"
EXIT_CODES = ("0 success; 1 a phase failed or did not verify (the files are still written); "
              "2 bad input (one line: file, place, what is wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """--out and --rules."""
    parser.add_argument("--out", metavar="DIR", default="out/demo",
                        help="where to write the run's files (out/demo)")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")


def _operator_lines(plan: dict[str, Any], name: str) -> list[str]:
    """One operator in the spirit of Fig. 22's long form."""
    op = plan["operators"][name]

    def plot(p: list) -> str:
        if p[0] == "$action":
            return f"($action {p[1]})"
        return f"({p[0]} " + " ".join(plot(x) for x in p[1:]) + ")"

    return [f"  ($action {name}  [{op['class']}]",
            f"     :base ({' '.join(op['base'])})  :target ({' '.join(op['target'])})",
            f"     :plot {plot(op['plot'])})"]


def top_of_plan(plan: dict[str, Any]) -> list[str]:
    """The root operator and the operators its plot names (Fig. 22's two levels)."""
    root = plan["root"]
    lines = [";;; top level", *_operator_lines(plan, root), ";;; expansion level 1"]
    stack = [plan["operators"][root]["plot"]]
    while stack:
        p = stack.pop(0)
        if p[0] == "$action":
            lines += _operator_lines(plan, p[1])
        else:
            stack[:0] = list(p[1:])
    return lines


def run(args: argparse.Namespace) -> int:
    """Run the pipeline on scenarios/build-table.yaml and print the paper's figures."""
    from lbw_engine.pipeline.run import publish
    from lbw_engine.pipeline.run import run as pipeline
    from perception.world.scenario import load

    scenario = load(bundled_scenario("build-table"))
    print(f"lbw demo: watching '{scenario.name}' through the top and side cameras ...", flush=True)
    with OutputDir(args.out, inputs=[args.rules] if args.rules else []) as out:
        result = pipeline(scenario, args.rules)
        publish(result, out)
    rec = result.recognition
    names = [str(op).lower() for op in rec["recognized"]]
    print(f"\nRecognized {len(names)} operations (Fig. 20), "
          f"{'exactly' if rec['exact'] else 'NOT'} as demonstrated:")
    for start in range(0, len(names), 4):
        print("  " + " ".join(names[start:start + 4]))
    if result.plan is not None:
        print(f"\nLearned plan, {len(result.plan['operators'])} operators; "
              "top two levels (Fig. 22):")
        print("\n".join(top_of_plan(result.plan)))
    if result.execution is not None:
        n = result.execution.report.get("commands", 0)
        print(f"\nExecution in a new layout: {n} manipulator commands (the paper: 45)")
    verdict = "SUCCESS" if result.success else f"FAILED: {result.failure}"
    print(f"Verdict: {verdict}\nFiles: {args.out}/"
          "{actions.json, plan.json, plan.txt, commands.txt, execution.json}")
    if not result.success:
        print(f"lbw demo: {result.failure}", file=sys.stderr)
        return 1
    return 0
