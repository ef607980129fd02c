"""``lbw check [RULES_DIR]``: validate every rule file, alone and against each other."""

from __future__ import annotations

import argparse
from pathlib import Path

from lbw_engine.errors import InputError
from lbw_engine.guard import shorten
from lbw_engine.rules import RULE_FILES, load_rules
from lbw_engine.rules import commands as commandrules
from lbw_engine.understand import load_rules as load_analysis_rules
from lbw_engine.understand import load_templates
from lbw_engine.understand.plottext import check_grammar as check_plot_grammar

HELP = "validate rule files (exit 2 with file:line on the first problem)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """RULES_DIR is optional: the bundled rules/ by default."""
    parser.add_argument("rules_dir", nargs="?", metavar="RULES_DIR", help="folder of rule files")


def _line_naming(path: Path, word: str) -> int | None:
    """First line of ``path`` that mentions ``word`` (for a cross-file message)."""
    try:
        for number, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if word in text and not text.lstrip().startswith(("#", "//")):
                return number
    except OSError:
        return None
    return None


def cross_check(operations: set[str], named: list[tuple[set[str], Path, str]]) -> None:
    """Operations named by the templates (Fig. 15), the analysis table and the
    command expansions (Table IX) must be operations the recognizer's rules
    (Table V) define; ``named`` holds (names, file, what names them)."""
    for words, path, what in named:
        for word in sorted(words - operations):
            raise InputError(
                f"the {what} names operation {shorten(word)}, which the recognizer's "
                f"operations.yaml does not define (known: {', '.join(sorted(operations))})",
                file=path, line=_line_naming(path, word))


def run(args: argparse.Namespace) -> int:
    """Load every rule file and cross-check them; InputError (exit 2) names file and line."""
    rules = load_rules(args.rules_dir)
    analysis = load_analysis_rules(rules.directory)
    templates = load_templates(analysis)
    check_plot_grammar(analysis.plot_grammar_file, rules.hold_relation)
    commands = commandrules.load_dir(rules.directory)
    words = {t.pattern.value for t in templates.parser.terminals if t.pattern.type == "str"}
    cross_check(rules.operations, [
        (words, templates.file, "template"),
        (set(analysis.trailing), analysis.file, "analysis table (templates.trailing)"),
        (set(commands.operations), Path(commands.file), "command expansion"),
    ])
    print(
        f"lbw check: {rules.directory}: {len(RULE_FILES) + 4} rule files OK "
        f"({len(rules.events)} events, {len(rules.motions)} motion classes, "
        f"{len(rules.operations)} operations, {len(rules.transitions)} transitions, "
        f"{sum(len(r) for r in rules.redirections.values())} redirections, "
        f"{len(templates.parser.rules)} template rules, {len(commands.macros)} command macros)"
    )
    return 0
