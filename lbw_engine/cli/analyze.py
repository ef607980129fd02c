"""``lbw analyze ACTIONS.json --out DIR [--repair]``: learn the task plan from an action sequence.

Writes plan.json and plan.txt (design.md "Plan") into DIR through OutputDir,
so bad input (exit 2) leaves no partial output. The sequence is analysed as
written; with ``--repair`` it is first checked against rules/domain.yaml and
repaired where exactly one single change fits (Sec. IX-C2, docs/repair.md),
each change is printed, and the repaired sequence, with its ``repairs``, is
written as DIR/actions.json too.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.outputs import OutputDir
from lbw_engine.understand import analyze_file, write_plan_text

HELP = "analyze a recognized action sequence (actions.json) into a task plan"
EXIT_CODES = ("0 plan.json and plan.txt written; 2 bad input (one line: file, place, what is "
              "wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """ACTIONS.json, --out DIR, --rules DIR, --repair."""
    parser.add_argument("actions", metavar="ACTIONS.json", help="recognized action sequence")
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="where to write plan.json and plan.txt "
                             "(default: the folder of ACTIONS.json)")
    parser.add_argument("--rules", metavar="DIR", default=None,
                        help="rule folder (default: bundled rules/)")
    parser.add_argument("--repair", action="store_true",
                        help="repair the sequence first where rules/domain.yaml allows exactly "
                             "one single change (Sec. IX-C2); also writes DIR/actions.json")


def run(args: argparse.Namespace) -> int:
    """Analyse (after repair when asked), then publish plan.json and plan.txt together."""
    out = Path(args.out) if args.out else Path(args.actions).resolve().parent
    repaired = None
    if args.repair:
        if (out / "actions.json").resolve() == Path(args.actions).resolve():
            raise InputError("--repair writes DIR/actions.json, which is ACTIONS.json itself; "
                             "give --out another folder", file=args.actions, where="--out")
        result, repaired = _repaired(args)
    else:
        result = analyze_file(args.actions, args.rules)
    inputs = [args.actions, *([args.rules] if args.rules else [])]
    flag = "--out" if args.out else "--out (default: the folder of ACTIONS.json)"
    with OutputDir(out, inputs=inputs, flag=flag) as staged:
        staged.write_json("plan.json", result.plan)
        staged.write_text("plan.txt", write_plan_text(result.plan))
        if repaired is not None:
            staged.write_json("actions.json", repaired.actions)
    if repaired is not None:
        _report(repaired, out)
    n_achieve = sum(1 for op in result.operators.values() if op.cls == "ACHIEVE")
    removed = " ".join(op.name for op in result.removed) or "none"
    print(f"lbw analyze: {len(result.operators)} operators ({n_achieve} ACHIEVE), "
          f"root {result.root.name}; redundant operations removed: {removed}; "
          f"wrote {out / 'plan.json'} and {out / 'plan.txt'}")
    return 0


def _repaired(args: argparse.Namespace) -> tuple[Any, Any]:
    """Check, repair, then analyse the repaired sequence."""
    from lbw_engine.rules import load_rules
    from lbw_engine.understand import RelationTable, analyze, parse_actions
    from lbw_engine.understand.actions import read_actions
    from lbw_engine.understand.repair import repair_actions

    rules = load_rules(args.rules)
    doc = read_actions(args.actions)
    parse_actions(doc, RelationTable(rules.analysis.tolerance), str(args.actions),
                  rules.hold_relation)  # bad input
    repaired = repair_actions(doc, rules)
    seq = parse_actions(repaired.actions, RelationTable(rules.analysis.tolerance),
                        str(args.actions))
    return analyze(seq, rules.analysis), repaired


def _report(repaired: Any, out: Path) -> None:
    """Every change, and what stayed inconsistent (never repair silently)."""
    from lbw_engine.pipeline.run import repair_lines

    for line in repair_lines(repaired.actions):
        print(f"lbw analyze: {line}")
    for left in repaired.left:
        print(f"lbw analyze: left as recognized: {left}")
    print(f"lbw analyze: {len(repaired.repairs)} repair(s); wrote {out / 'actions.json'}")
