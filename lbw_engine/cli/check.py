"""``lbw check [RULES_DIR]``: validate every rule file, alone and against each other.

One loader reads every file of the folder (lbw_engine.rules.load_rules); the
rules are then checked against the vocabulary of the image detectors: every
event must ask its detector a method the detector answers, every Table V value
must stand for an answer the detector gives.
"""

from __future__ import annotations

import argparse

from lbw_engine.rules import RULE_FILES, check_detectors, load_rules
from lbw_engine.rules.check import check_expansions
from lbw_engine.understand.plottext import check_grammar as check_plot_grammar

HELP = "validate rule files (exit 2 with file:line on the first problem)"
EXIT_CODES = ("0 the rule files are valid; 2 a rule file is bad (one line: file, line, what is "
              "wrong); 3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DIR is optional: the bundled rules/ by default."""
    parser.add_argument("rules_dir", nargs="?", metavar="DIR",
                        help="folder of rule files (default: bundled rules/)")


def run(args: argparse.Namespace) -> int:
    """Load every rule file and cross-check them; InputError (exit 2) names file and line."""
    from perception.vision.envnodes import vocabulary

    rules = load_rules(args.rules_dir)
    check_detectors(rules, vocabulary())
    check_expansions(rules)
    # plot.lark must read back what lbw writes to plan.txt (it compiled when loading)
    check_plot_grammar(rules.analysis.plot_grammar_file, rules.roles.multiple)
    commands = rules.commands
    print(
        f"lbw check: {rules.directory}: {len(RULE_FILES)} rule files OK "
        f"({len(rules.events)} events, {len(rules.motions)} motion classes, "
        f"{len(rules.operations)} operations, {len(rules.transitions)} transitions, "
        f"{sum(len(r) for r in rules.redirections.values())} redirections, "
        f"{len(rules.analysis.templates().parser.rules)} template rules, "
        f"{len(commands.macros)} command macros, "
        f"{len(rules.domain.operations)} operations in the symbolic domain)"
    )
    return 0
