"""``lbw recognize TRACE --out DIR [--rules DIR]``: recognize actions from an event trace."""

from __future__ import annotations

import argparse
import sys

from lbw_engine.outputs import OutputDir
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.see.replay import recognize_trace

HELP = "recognize the action sequence of a recorded event trace; writes actions.json"
EXIT_CODES = ("0 actions.json written; 2 bad input (one line: file, place, what is wrong); "
              "3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """TRACE, --out and --rules."""
    parser.add_argument("trace", metavar="TRACE", help="event trace (docs/replay-trace.md)")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")


def run(args: argparse.Namespace) -> int:
    """Replay the trace through the interpreter and publish actions.json."""
    rules = load_rules(args.rules)
    recognizer, trace = recognize_trace(args.trace, rules)
    with OutputDir(args.out, inputs=[args.trace, *([args.rules] if args.rules else [])]) as out:
        path = out.write_json("actions.json", to_actions(recognizer))
    ops = [op["operation"] for op in to_actions(recognizer)["operations"]]
    unused = trace.unused()
    if unused:
        lines = ", ".join(str(r.line) for r in unused[:10])
        print(f"lbw recognize: note: {len(unused)} trace records were not asked for "
              f"(lines {lines})", file=sys.stderr)
    print(f"lbw recognize: {len(ops)} operations -> {path}")
    return 0
