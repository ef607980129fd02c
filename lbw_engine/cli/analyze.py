"""``lbw analyze ACTIONS.json --out DIR``: learn the task plan from an action sequence.

Writes plan.json and plan.txt (design.md "Plan") into DIR through OutputDir,
so bad input (exit 2) leaves no partial output.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from lbw_engine.outputs import OutputDir
from lbw_engine.understand import analyze_file, write_plan_text

HELP = "analyze a recognized action sequence (actions.json) into a task plan"
EXIT_CODES = ("0 plan.json and plan.txt written; 2 bad input (one line: file, place, what is "
              "wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """ACTIONS.json, --out DIR, --rules DIR."""
    parser.add_argument("actions", metavar="ACTIONS.json", help="recognized action sequence")
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="where to write plan.json and plan.txt "
                             "(default: the folder of ACTIONS.json)")
    parser.add_argument("--rules", metavar="DIR", default=None,
                        help="rule folder (default: bundled rules/)")


def run(args: argparse.Namespace) -> int:
    """Analyse, then publish plan.json and plan.txt together."""
    result = analyze_file(args.actions, args.rules)
    out = Path(args.out) if args.out else Path(args.actions).resolve().parent
    inputs = [args.actions, *([args.rules] if args.rules else [])]
    flag = "--out" if args.out else "--out (default: the folder of ACTIONS.json)"
    with OutputDir(out, inputs=inputs, flag=flag) as staged:
        staged.write_json("plan.json", result.plan)
        staged.write_text("plan.txt", write_plan_text(result.plan))
    n_achieve = sum(1 for op in result.operators.values() if op.cls == "ACHIEVE")
    removed = " ".join(op.name for op in result.removed) or "none"
    print(f"lbw analyze: {len(result.operators)} operators ({n_achieve} ACHIEVE), "
          f"root {result.root.name}; redundant operations removed: {removed}; "
          f"wrote {out / 'plan.json'} and {out / 'plan.txt'}")
    return 0
