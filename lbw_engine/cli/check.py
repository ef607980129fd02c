"""``lbw check [RULES_DIR]``: validate the rule files."""

from __future__ import annotations

import argparse

from ..rules import RULE_FILES, load_rules

HELP = "validate rule files (exit 2 with file:line on the first problem)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """RULES_DIR is optional: the bundled rules/ by default."""
    parser.add_argument("rules_dir", nargs="?", metavar="RULES_DIR", help="folder of rule files")


def run(args: argparse.Namespace) -> int:
    """Load every rule file; InputError (exit 2) names the file and line of a problem."""
    rules = load_rules(args.rules_dir)
    print(
        f"lbw check: {rules.directory}: {len(RULE_FILES)} rule files OK "
        f"({len(rules.events)} events, {len(rules.motions)} motion classes, "
        f"{len(rules.operations)} operations, {len(rules.transitions)} transitions, "
        f"{sum(len(r) for r in rules.redirections.values())} redirections)"
    )
    return 0
