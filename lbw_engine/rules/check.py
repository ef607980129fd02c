"""Checks that span rule files: every reference exists, and every row can fire.

A row "can never fire" when its motion class is never instantiated, when no
ATTN-node of that class ever waits for its event, or (Table V) when an earlier
row already matches whenever it does (checked in ``recognition``). Operations
named by the templates, the analysis table and the command expansions must be
operations of Table V; events must ask what their detectors answer.
"""

from __future__ import annotations

from pathlib import Path

from lbw_engine.errors import InputError
from lbw_engine.guard import shorten
from lbw_engine.rules import records as R
from lbw_engine.rules.reader import listing


def _keys_of(rules: R.RuleSet) -> set[str]:
    """Everything an interpretation may be keyed by: events and motion-feature values."""
    return set(rules.events) | set(rules.motion_features.values())


def _reachable(rules: R.RuleSet) -> set[str]:
    """Motion classes that can ever be instantiated (from the start class)."""
    seen = {rules.start_motion().name}
    changed = True
    while changed:
        changed = False
        for row in rules.transitions.values():
            if row.motion in seen and row.next and row.next not in seen:
                seen.add(row.next)
                changed = True
    return seen


def _awaited(rules: R.RuleSet, motion: str) -> set[str]:
    """Keys an ACT-node of ``motion`` can receive: its ATTN-nodes' events and their values."""
    events = {r.event for r in rules.redirections.get(motion, ()) if r.op != "delete"}
    keys = set(events)
    for event in events:
        if event in rules.motion_features.ranges:
            keys |= set(rules.motion_features.values())
    return keys


def _check_transitions(rules: R.RuleSet, reachable: set[str]) -> None:
    keys = _keys_of(rules)
    for row in rules.transitions.values():
        if row.motion not in rules.motions:
            raise row.at.error(f"motion class {row.motion!r} does not exist")
        if row.key not in keys:
            raise row.at.error(f"event {row.key!r} does not exist")
        if row.next is not None:
            if row.next not in rules.motions:
                raise row.at.error(f"next motion class {row.next!r} does not exist")
            level, nxt = rules.motions[row.motion].level, rules.motions[row.next].level
            want = level + 1 if row.direction == "down" else level
            if nxt != want:
                raise row.at.error(
                    f"a {row.direction!r} transition from level {level} must lead to level "
                    f"{want}, but {row.next} is at level {nxt}"
                )
    for row in rules.transitions.values():
        if row.motion not in reachable:
            raise row.at.error(f"this row can never fire: no transition creates {row.motion}")
        if row.key not in _awaited(rules, row.motion):
            raise row.at.error(
                f"this row can never fire: no ATTN-node of {row.motion} waits for {row.key!r}"
            )


def _check_redirections(rules: R.RuleSet) -> None:
    keys = _keys_of(rules)
    for motion, rows in rules.redirections.items():
        for row in rows:
            if motion not in rules.motions:
                raise row.at.error(f"motion class {motion!r} does not exist")
            if row.key != R.INIT and row.key not in keys:
                raise row.at.error(f"event {row.key!r} does not exist")
            if row.event is not None and row.event not in rules.events:
                raise row.at.error(f"event {row.event!r} does not exist")


def _check_redirections_fire(rules: R.RuleSet, reachable: set[str]) -> None:
    for motion, rows in rules.redirections.items():
        for row in rows:
            if motion not in reachable:
                raise row.at.error(f"this row can never fire: no transition creates {motion}")
            if row.key != R.INIT and row.key not in _awaited(rules, motion):
                raise row.at.error(
                    f"this row can never fire: no ATTN-node of {motion} waits for {row.key!r}"
                )


def _check_effects(rules: R.RuleSet) -> None:
    for op, rule in rules.effects.items():
        if op not in rules.operations:
            raise rule.at.error(f"operation {op!r} does not exist in operations.yaml")
        bound = set(rule.bind)
        for name, value in rule.bind.items():
            feature = value.get("to", value.get("found")) if isinstance(value, dict) else None
            if feature is not None and (not isinstance(feature, str)
                                        or feature not in rules.features):
                raise rule.at.error(f"feature {shorten(feature)} of binding {name!r} does not "
                                    "exist")

        def var(text: str, at: R.Where, star_ok: bool = False, bound=bound, op=op) -> None:
            """A template term must be '*' or a variable the rule binds."""
            if text == "*":
                return
            if not isinstance(text, str) or not text.startswith("$"):
                raise at.error(f"{shorten(text)} is neither a variable ($name) nor '*'")
            name = text[1:-1] if star_ok and text.endswith("*") else text[1:]
            if name not in bound:
                raise at.error(f"variable ${name} is not bound in 'bind' of {op}")

        for tpl in (*rule.remove, *rule.add):
            var(tpl.subject, tpl.at, star_ok=True)
            var(tpl.object, tpl.at)
            if tpl.wrt is not None:
                var(tpl.wrt, tpl.at)
            if tpl.when is not None:
                var(tpl.when[1], tpl.at)
        for key, value in rule.move.items():
            if key == "measured":
                if not isinstance(value, str) or value not in rules.features:
                    raise rule.at.error(f"feature {shorten(value)} in move does not exist")
            else:
                var(value, rule.at)


def check(rules: R.RuleSet) -> None:
    """Raise InputError (file:line) on the first inconsistency across rule files."""
    for feature in rules.features.values():
        if feature.detector is not None and feature.detector not in rules.detectors:
            raise feature.at.error(f"detector {feature.detector!r} does not exist")
    rules.operations = {row.operation for rows in rules.classification.values() for row in rows}
    _check_redirections(rules)
    reachable = _reachable(rules)
    _check_transitions(rules, reachable)
    _check_redirections_fire(rules, reachable)
    for motion, rows in rules.classification.items():
        if motion not in reachable:
            raise rows[0].at.error(f"this row can never fire: no transition creates {motion}")
    _check_effects(rules)


def _line_naming(path: Path, word: str) -> int | None:
    """First line of ``path`` that mentions ``word`` outside comments (for a message)."""
    try:
        for number, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if word in text and not text.lstrip().startswith(("#", "//")):
                return number
    except (OSError, UnicodeDecodeError):
        return None
    return None


def check_named_operations(rules: R.RuleSet) -> None:
    """Operations named by templates.lark, analysis.yaml and commands.yaml exist (Table V)."""
    analysis, commands = rules.analysis, rules.commands
    named = [
        (analysis.templates().words(), analysis.grammar_file, "template", {}),
        (set(analysis.trailing), analysis.file, "analysis table (templates.trailing)", {}),
        (set(commands.operations), Path(commands.file), "command expansion",
         {n: o.line for n, o in commands.operations.items()}),
    ]
    for words, path, what, lines in named:
        for word in sorted(words - rules.operations):
            raise InputError(
                f"the {what} names operation {word!r}, which the recognizer's operations.yaml "
                f"does not define (known: {listing(sorted(rules.operations))})",
                file=path, line=lines.get(word) or _line_naming(path, word))


def check_expansions(rules: R.RuleSet) -> None:
    """Every operation the templates put in plans has an expansion in commands.yaml: the
    robot can do any plan (``lbw check`` only: a rule set for analysis alone may leave it
    out; round 15: a copy without the grasp's expansion failed at instantiation)."""
    analysis, commands = rules.analysis, rules.commands
    for word in sorted(analysis.templates().words() - set(commands.operations)):
        raise InputError(
            f"operations: no expansion for {word!r}, which the templates "
            f"({analysis.grammar_file.name}) put in plans (expanded: "
            f"{listing(sorted(commands.operations))})",
            file=Path(commands.file), line=_line_naming(Path(commands.file), "operations:"))


def check_vocabulary(rules: R.RuleSet, vocabulary: dict[str, dict[str, frozenset]]) -> None:
    """Every event asks its detector a method it answers; every snapshot-diff value maps
    to an answer its detector gives (the detectors' closed vocabulary)."""
    for event in rules.events.values():
        spec = rules.detectors[event.detector]
        if spec.builtin is not None:
            continue
        methods = vocabulary.get(event.detector, {}).get("methods", frozenset())
        if event.method not in methods:
            raise event.at.error(
                f"event {event.name!r} asks {event.detector} for {event.method!r}, which it "
                f"does not answer (it answers: {listing(sorted(methods)) or 'nothing'})")
    for feature in rules.features.values():
        if feature.source != "snapshot-diff":
            continue
        answers = vocabulary.get(feature.detector, {}).get("answers", frozenset())
        for value, answer in feature.answers.items():
            if answer not in answers:
                shown = listing(sorted(map(str, answers))) or "nothing"
                raise feature.at.error(
                    f"feature {feature.name!r}: value {value!r} stands for {answer!r}, which "
                    f"{feature.detector} never answers (it answers: {shown})")
