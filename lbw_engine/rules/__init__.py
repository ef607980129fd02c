"""Rule loading: every file of rules/, read by one loader and checked by one validator.

``load_rules(dir)`` parses the recognition tables (Tables III-VIII, Sec. V-B4),
analysis.yaml with its two Lark grammars (Fig. 15, 17) and commands.yaml
(Table IX), then cross-checks them (``check``); nothing runs until all of them
load and agree. ``check_detectors`` checks the rules against the vocabulary a
detector registry declares (which methods each detector answers, which answers
it gives). Every error names the file and line.
"""

from __future__ import annotations

from pathlib import Path

from lbw_engine.errors import InputError
from lbw_engine.rules.records import (
    BINDINGS,
    DIRECTION_TESTS,
    DIRECTIONS,
    FEATURE_SOURCES,
    INIT,
    RULE_FILES,
    SLOTS,
    SPEED_TESTS,
    STACK_OPS,
    Binding,
    ClassRow,
    DetectorDef,
    EffectRule,
    EventDef,
    FeatureDef,
    FeatureValueRow,
    MotionClass,
    MotionFeatures,
    RedirectionRow,
    Roles,
    RuleSet,
    Template,
    TransitionRow,
    Where,
)

__all__ = [
    "BINDINGS", "DIRECTIONS", "DIRECTION_TESTS", "FEATURE_SOURCES", "INIT", "RULE_FILES",
    "SLOTS", "SPEED_TESTS", "STACK_OPS", "Binding", "ClassRow", "DetectorDef", "EffectRule",
    "EventDef", "FeatureDef", "FeatureValueRow", "MotionClass", "MotionFeatures",
    "RedirectionRow", "Roles", "RuleSet", "Template", "TransitionRow", "Where",
    "check_detectors", "load_rules",
]


def load_rules(directory: str | Path | None = None) -> RuleSet:
    """Load and check every rule file of ``directory`` (default: the bundled rules)."""
    from lbw_engine.paths import default_rules_dir
    from lbw_engine.rules import analysis, check, commands, domain, recognition
    from lbw_engine.yamlio import load_file

    directory = Path(directory) if directory is not None else default_rules_dir()
    if not directory.exists():
        raise InputError("rules folder not found", file=directory)
    if not directory.is_dir():
        raise InputError("is not a folder of rule files", file=directory)
    rules = recognition.read_all(directory)
    check.check(rules)
    rules.analysis = analysis.parse(directory)
    path = directory / "commands.yaml"
    rules.commands = commands.parse(load_file(path), str(path), rules.roles.support,
                                    rules.labels(), tuple(rules.relations))
    check.check_named_operations(rules)
    rules.domain = domain.parse(rules)
    return rules


def check_detectors(rules: RuleSet, vocabulary: dict[str, dict[str, frozenset]]) -> None:
    """The rules ask only what the detectors answer (lbw check; docs/engine.md).

    ``vocabulary`` maps a detector name to ``{"methods": ..., "answers": ...}``:
    the event methods it answers and the snapshot comparisons' answers it gives.
    """
    from lbw_engine.rules import check

    check.check_vocabulary(rules, vocabulary)
