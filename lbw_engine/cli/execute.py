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

from lbw_engine.do import plan as planmod
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.execute import VIA, execute_plan, write_views
from lbw_engine.rules import load_rules

HELP = "Instantiate a plan in the scenario's execution workspace, run it with the robot, verify."


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Arguments of ``lbw execute``."""
    p.add_argument("plan", help="plan.json written by `lbw analyze`")
    p.add_argument("scenario", help="scenario YAML with an `execute` workspace")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--rules", default=None, help="rules directory (default: bundled rules/)")
    p.add_argument("--via", choices=VIA, default=VIA[0],
                   help="trace: run the traced commands; bt: tick the plan's behaviour tree "
                        "(lbw_engine/do/behaviour.py)")


def run(args: argparse.Namespace) -> int:
    """Run the command; see the module docstring."""
    from perception.world import scenario as scenario_mod

    rules = load_rules(args.rules)
    plan = planmod.load(args.plan)
    sc = scenario_mod.load(args.scenario)
    with OutputDir(args.out) as out:
        result = execute_plan(plan, sc, rules, via=args.via)
        out.write_text("commands.txt", result.commands_text)
        out.write_json("execution.json", result.report)
        write_views(out, result.views)
    if not result.success:
        print(f"lbw execute: {result.phase}: {result.message}", file=sys.stderr)
        return 1
    return 0
