"""`lbw check` validates every rule file, and the files against each other."""

import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.paths import default_rules_dir

# (case id, file to edit, text to replace, replacement, file named in the error, fragment)
BROKEN = [
    ("templates-unknown-operation", "templates.lark", '"PICK" _withdraw*',
     '"PICK-FROM-TABLE" _withdraw*', "templates.lark:", "PICK-FROM-TABLE"),
    ("templates-bad-grammar", "templates.lark", "achieve: fetch fake* put",
     "achieve: fetch fake* put (", "templates.lark", "bad template grammar"),
    ("commands-unknown-operation", "commands.yaml", "\n  ALIGN: ", "\n  ALIGNX: ",
     "commands.yaml:", "ALIGNX"),
    ("analysis-trailing-unknown-operation", "analysis.yaml", "trailing: [WITHDRAW]",
     "trailing: [WITHDRAWAL]", "analysis.yaml:", "WITHDRAWAL"),
    ("analysis-unknown-rule", "analysis.yaml", "achieve", "achieve_typo",
     "analysis.yaml", "achieve_typo"),
]


@pytest.fixture
def rules_copy(tmp_path: Path) -> Path:
    target = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), target, ignore=shutil.ignore_patterns("__pycache__"))
    return target


def test_bundled_rules_pass(capsys):
    assert main(["check"]) == 0
    assert "rule files OK" in capsys.readouterr().out


@pytest.mark.parametrize("case", BROKEN, ids=[c[0] for c in BROKEN])
def test_broken_copy_fails_with_file_and_line(case, rules_copy, capsys):
    _, name, old, new, named, fragment = case
    path = rules_copy / name
    text = path.read_text()
    assert old in text, f"fixture out of date: {old!r} not in {name}"
    path.write_text(text.replace(old, new, 1))
    assert main(["check", str(rules_copy)]) == 2
    err = capsys.readouterr().err
    assert named in err and fragment in err, err
    assert "Traceback" not in err
