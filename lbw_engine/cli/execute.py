"""``lbw execute PLAN.json SCENARIO --out DIR``: instantiate, execute and verify (Sec. VII).

Builds the scenario's execution workspace, measures it through the cameras,
matches it to the plan, runs the Table IX commands with the robot and verifies
the built structure (lbw_engine.pipeline.execute). Writes ``commands.txt``,
``execution.json`` and the initial and final camera views; exit 0 when verified,
1 when not (outputs are published first; ``failure`` names the phase), 2 on bad
input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lbw_engine.do import plan as planmod
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.execute import VIA, execute_plan, fault_notes, write_views
from lbw_engine.rules import load_rules

HELP = "instantiate a plan in the scenario's execution workspace, run it with the robot, verify"
EXIT_CODES = ("0 the built structure verifies; 1 instantiation or execution failed or did not "
              "verify (the files are still written); 2 bad input (one line: file, place, what is "
              "wrong); 3 internal error")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Arguments of ``lbw execute``."""
    p.add_argument("plan", metavar="PLAN.json", help="plan written by `lbw analyze`")
    p.add_argument("scenario", metavar="SCENARIO",
                   help="scenario YAML file with an `execute` workspace")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument("--rules", metavar="DIR", default=None,
                   help="rule folder (default: bundled rules/)")
    p.add_argument("--via", choices=VIA, default=VIA[0], metavar="MODE",
                   help="trace: run the traced commands (default); bt: tick the plan's "
                        "behaviour tree (lbw_engine/do/behaviour.py)")


def run(args: argparse.Namespace) -> int:
    """Run the command; see the module docstring."""
    from perception.world import scenario as scenario_mod

    rules = load_rules(args.rules)
    plan = planmod.load(args.plan)
    sc = scenario_mod.load(args.scenario)
    with OutputDir(args.out, inputs=[args.plan, args.scenario, *([args.rules] if args.rules
                                                                   else [])],
                   keep=_continued(args.plan, args.out)) as out:
        result = execute_plan(plan, sc, rules, via=args.via)
        out.write_text("commands.txt", result.commands_text)
        out.write_json("execution.json", result.report)
        write_views(out, result.views)
    ran = result.report.get("commands")  # counted when the run reached its verdict
    done = f"plan {plan.root} in {sc.name}" + (f": {ran} commands" if ran is not None else "")
    for line in fault_notes(result.report):
        print(f"lbw execute: {line}", file=sys.stderr)
    if not result.success:
        print(f"lbw execute: {done}; failed: {result.phase}: {result.message}; outputs in "
              f"{args.out}", file=sys.stderr)
        return 1
    print(f"lbw execute: {done}; verified ({result.message}); outputs in {args.out}")
    return 0


def _continued(plan: str, out: str) -> list[str]:
    """The earlier phases' files kept when the plan is read from the output folder itself
    (``lbw execute d/plan.json S --out d`` continues the run in d)."""
    if Path(plan).resolve().parent != Path(out).resolve():
        return []
    return ["actions.json", "plan.txt"]
