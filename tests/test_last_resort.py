"""The last resort (issue #15): a bug is exit 3 with one line naming a crash file, never
a traceback on the terminal and never a half-written output; bad paths are exit 2."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.fuzzcases import run_lbw
from lbw_engine.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
ACTIONS = ROOT / "tests" / "data" / "fig20-build-table.actions.json"


def test_unexpected_exception_is_an_internal_error(tmp_path, monkeypatch):
    """A bug while the outputs are staged: exit 3, one line, details in a crash file."""
    def broken(plan):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr("lbw_engine.cli.analyze.write_plan_text", broken)
    out = tmp_path / "out"
    run = run_lbw(["analyze", str(ACTIONS), "--out", str(out)])
    assert run.code == 3 and not run.escaped
    assert "Traceback" not in run.stderr and len(run.stderr.splitlines()) == 1
    assert "internal error (ZeroDivisionError)" in run.stderr
    crash = Path(run.stderr.split("details in ")[1].strip())
    assert crash.parent == tmp_path  # beside the output folder
    details = crash.read_text()
    assert "Traceback (most recent call last)" in details and "a bug" in details
    assert f"lbw analyze {ACTIONS}" in details
    assert not out.exists() or list(out.iterdir()) == []  # the staged plan.json was not published


def test_crash_file_goes_to_the_temporary_folder_without_out(tmp_path, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr("lbw_engine.cli.check.load_rules", broken)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    run = run_lbw(["check"])
    assert run.code == 3 and str(tmp_path) in run.stderr
    assert len(list(tmp_path.glob("lbw-crash-check-*.txt"))) == 1


PATHS = [  # (case, argv builder, message fragment)
    ("input-missing", lambda t: ["analyze", str(t / "nope.json"), "--out", str(t / "o")],
     "nope.json: file not found"),
    ("input-is-a-folder", lambda t: ["analyze", str(t), "--out", str(t / "o")],
     "is a directory, expected an actions.json file"),
    ("out-is-a-file", lambda t: ["analyze", str(ACTIONS), "--out", str(t / "f")],
     "f: --out: names a file"),
    ("out-inside-a-file", lambda t: ["analyze", str(ACTIONS), "--out", str(t / "f" / "o")],
     "--out: cannot create the output folder here"),
    ("rules-missing", lambda t: ["check", str(t / "nope")], "nope: rules folder not found"),
    ("rules-is-a-file", lambda t: ["check", str(t / "f")], "is not a folder of rule files"),
    ("scenario-is-a-folder", lambda t: ["watch", str(t), "--out", str(t / "o")],
     "is a directory, expected a YAML file"),
]


@pytest.mark.parametrize("argv,fragment", [p[1:] for p in PATHS], ids=[p[0] for p in PATHS])
def test_bad_paths_are_bad_input(tmp_path, argv, fragment):
    (tmp_path / "f").write_text("a file\n")
    run = run_lbw(argv(tmp_path))
    assert run.code == 2 and len(run.stderr.splitlines()) == 1 and fragment in run.stderr, \
        run.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]


def test_exit_codes_are_documented():
    """`lbw --help` and the README name exit 3 beside 0, 1 and 2."""
    assert "3 an internal error" in " ".join(build_parser().format_help().split())
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert "3 on an internal error" in readme
