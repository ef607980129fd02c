"""``lbw demo``: recognize the bundled Build-Table event trace (Fig. 20) and print it."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..actions import to_actions
from ..replay import recognize_trace
from ..rules import load_rules

HELP = "run the recognizer on the bundled Build-Table event trace and print the sequence"
TRACE = Path(__file__).resolve().parent.parent / "data" / "build-table.trace.jsonl"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Only --rules."""
    parser.add_argument("--rules", metavar="DIR", help="rule folder (default: bundled rules/)")


def run(args: argparse.Namespace) -> int:
    """Print the recognized operations as in Fig. 20, then the last one's final state."""
    rules = load_rules(args.rules)
    recognizer, _ = recognize_trace(TRACE, rules)
    actions = to_actions(recognizer)
    ops = actions["operations"]
    print(f"Build Table (Fig. 20): {len(ops)} operations recognized from {TRACE.name}")
    names = [op["operation"].lower() for op in ops]
    for start in range(0, len(names), 4):
        print("  " + " ".join(names[start:start + 4]))
    placing = [op for op in ops if op["special"]]
    if placing:
        last = placing[-1]
        print(f"final state of {last['name']} (Fig. 21):")
        for rel in last["final_state"]["relations"]:
            print(f"  {rel}")
    return 0
