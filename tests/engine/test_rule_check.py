"""`lbw check` and the rule loader: a table of broken rule copies, one per kind of
error, each reported with the file and the line of the offending row."""

import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.errors import InputError
from lbw_engine.paths import default_rules_dir
from lbw_engine.rules import load_rules

# (case id, file, old text, new text, marker on the expected line, message fragment)
BROKEN = [
    (
        "unknown-key",
        "events.yaml",
        "    detector: object-finder\n",
        "    detector: object-finder\n    colour: red\n",
        "colour: red",
        "unknown key 'colour'",
    ),
    (
        "unknown-detector",
        "events.yaml",
        "detector: visual-search",
        "detector: visual-serch",
        "visual-serch",
        "detector 'visual-serch' does not exist",
    ),
    (
        "unknown-event-in-vii",
        "transitions.yaml",
        "event: far,",
        "event: farr,",
        "farr",
        "event 'farr' does not exist",
    ),
    (
        "unknown-motion-in-viii",
        "attention.yaml",
        "{motion: Depart,",
        "{motion: Departt,",
        "Departt",
        "motion class 'Departt' does not exist",
    ),
    (
        "unknown-next-motion",
        "transitions.yaml",
        "{motion: Depart, event: join, transition: next, next: FineMotion}",
        "{motion: Depart, event: join, transition: next, next: FineMotoin}",
        "FineMotoin",
        "next motion class 'FineMotoin' does not exist",
    ),
    (
        "unknown-operation-in-effects",
        "effects.yaml",
        "  ALIGN:\n",
        "  ALIGNN:\n",
        "ALIGNN:",
        "operation 'ALIGNN' does not exist",
    ),
    (
        "unknown-feature-value",
        "operations.yaml",
        "sil-diff: decreased",
        "sil-diff: smaller",
        "smaller",
        "value of 'sil-diff': 'smaller' does not exist",
    ),
    (
        "unknown-named-slot",
        "operations.yaml",
        "    names: target\n",
        "    names: targets\n",
        "names: targets",
        "feature 'sil-diff' names 'targets' does not exist (known: target)",
    ),
    (
        "named-slot-on-a-feature-without-detector",
        "operations.yaml",
        "  seg-event: {source: final-event}\n",
        "  seg-event: {source: final-event, names: target}\n",
        "seg-event:",
        "feature 'seg-event' of source 'final-event' takes no 'names'",
    ),
    (
        "unknown-binding",
        "transitions.yaml",
        "base: found, target: none",
        "base: founds, target: none",
        "founds",
        "binding 'base': 'founds' does not exist",
    ),
    (
        "duplicate-vii-row",
        "transitions.yaml",
        "  - {motion: Task, event: disappeared, transition: up}\n",
        "  - {motion: Task, event: disappeared, transition: up}\n"
        "  - {motion: Task, event: disappeared, transition: up}  # again\n",
        "# again",
        "duplicate row for Task on 'disappeared'",
    ),
    (
        "duplicate-viii-row",
        "attention.yaml",
        '  - {motion: LocalMotion, on: "true", op: delete}\n',
        '  - {motion: LocalMotion, on: "true", op: delete}\n'
        '  - {motion: LocalMotion, on: "true", op: delete}  # again\n',
        "# again",
        "duplicate row for LocalMotion",
    ),
    (
        "duplicate-iv-row",
        "motion-features.yaml",
        "  - {value: moving-fast, speed: fast}\n",
        "  - {value: moving-fast, speed: fast}\n  - {value: zooming, speed: fast}\n",
        "zooming",
        "can never fire",
    ),
    (
        "shadowed-v-row",
        "operations.yaml",
        "    - {when: {seg-event: near, hold: false}, operation: REACH}\n",
        "    - {operation: WITHDRAW}\n"
        "    - {when: {seg-event: near, hold: false}, operation: REACH}\n",
        "operation: REACH}",
        "can never fire",
    ),
    (
        "vii-row-never-fires",
        "transitions.yaml",
        "  - {motion: Task, event: disappeared, transition: up}\n",
        "  - {motion: Task, event: disappeared, transition: up}\n"
        "  - {motion: Transfer, event: join, transition: up}  # no ATTN-node waits\n",
        "no ATTN-node waits",
        "can never fire: no ATTN-node of Transfer waits for 'join'",
    ),
    (
        "viii-row-never-fires",
        "attention.yaml",
        "  - {motion: Approach, on: init, op: add, event: join, base: base, target: target}\n",
        "  - {motion: Approach, on: init, op: add, event: join, base: base, target: target}\n"
        "  - {motion: Approach, on: split, op: add, event: far}  # never\n",
        "# never",
        "can never fire",
    ),
    (
        "down-to-wrong-level",
        "transitions.yaml",
        "transition: down, next: Transfer",
        "transition: down, next: Approach",
        "next: Approach,",
        "must lead to level 1",
    ),
    (
        "unbound-effect-variable",
        "effects.yaml",
        "- [coplanar, $object, $other]",
        "- [coplanar, $object, $others]",
        "$others",
        "variable $others is not bound",
    ),
    (
        "unquoted-true",
        "attention.yaml",
        'ColdBoot, on: init, op: add, event: "true"',
        "ColdBoot, on: init, op: add, event: true",
        "event: true, base",
        "reads as a boolean",
    ),
    (
        "bad-yaml",
        "constants.yaml",
        "search-cycle-limit: 4",
        "search-cycle-limit: [4",
        "motion-detector-interval",
        "invalid YAML",
    ),
    (
        "bad-constant",
        "constants.yaml",
        "search-cycle-limit: 4",
        "search-cycle-limit: -4",
        "search-cycle-limit",
        "expected a number in [1, 20]",
    ),
    # round 15: both passed the check and failed at run time (exit 1)
    (
        "table-v-value-without-a-row",
        "operations.yaml",
        '    - {when: {sil-diff: no-change}, operation: NO-OP, label: "no"}'
        '   # "no01" in Fig. 12\n',
        "",
        "LocalMotion:",
        "no LocalMotion row matches {sil-diff: no-change",
    ),
]


def broken_copy(tmp_path: Path, file: str, old: str, new: str) -> Path:
    copy = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), copy)
    text = (copy / file).read_text()
    assert text.count(old) == 1, f"the case's text must occur once in {file}: {old!r}"
    (copy / file).write_text(text.replace(old, new))
    return copy


def line_with(path: Path, marker: str) -> int:
    lines = path.read_text().splitlines()
    return next(i for i, line in enumerate(lines, start=1) if marker in line)


def test_bundled_rules_pass(capsys):
    assert main(["check"]) == 0
    assert "rule files OK" in capsys.readouterr().out


@pytest.mark.parametrize(
    "file,old,new,marker,message", [c[1:] for c in BROKEN], ids=[c[0] for c in BROKEN]
)
def test_broken_copy_names_file_and_line(tmp_path, file, old, new, marker, message):
    copy = broken_copy(tmp_path, file, old, new)
    with pytest.raises(InputError) as err:
        load_rules(copy)
    assert Path(err.value.file).name == file
    expected = line_with(copy / file, marker)
    if message != "invalid YAML":  # a YAML parser reports where it noticed the problem
        assert err.value.line == expected
    assert message in err.value.message


def test_cli_check_broken_copy(tmp_path, capsys):
    copy = broken_copy(tmp_path, *BROKEN[2][1:4])
    assert main(["check", str(copy)]) == 2
    err = capsys.readouterr().err
    line = line_with(copy / "transitions.yaml", "farr")
    assert f"transitions.yaml:{line}:" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_missing_rule_file(tmp_path, capsys):
    copy = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), copy)
    (copy / "effects.yaml").unlink()
    assert main(["check", str(copy)]) == 2
    assert "effects.yaml: file not found" in capsys.readouterr().err


def test_missing_rules_folder(tmp_path, capsys):
    assert main(["check", str(tmp_path / "nowhere")]) == 2
    assert "rules folder not found" in capsys.readouterr().err


def test_check_refuses_a_planned_operation_without_expansion(tmp_path, capsys):
    """Round 15: a copy without PICK's commands.yaml entry passed `lbw check` and failed
    at instantiation. `lbw check` refuses it (a copy for analysis alone still loads)."""
    copy = broken_copy(tmp_path, "commands.yaml",
                       "  PICK:           {goal: [object], steps: [[PICK, goal]], "
                       "check-jaws: true}\n", "")
    load_rules(copy)
    assert main(["check", str(copy)]) == 2
    err = capsys.readouterr().err
    assert "commands.yaml:" in err and "no expansion for 'PICK'" in err
