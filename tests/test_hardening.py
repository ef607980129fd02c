"""Issue #15, row by row: every input that reached a traceback (or slipped through)
now gets exit 2 and one line naming the file and the place.

One table: (cause, the command's input, expected exit, fragment of the message).
Inputs are edits of bundled files, made in a temporary folder; commands run
through ``lbw_engine.cli.main`` in-process (bench/fuzzcases.run_lbw, with
``lbw watch`` stopped after the scenario loader, ``lbw execute`` before the world).
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from bench.fuzzcases import run_lbw
from bench.mutators import alias_bomb as bomb
from lbw_engine.guard import shorten
from lbw_engine.yamlio import loads

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
SCENARIO = ROOT / "scenarios" / "build-table.yaml"
ACTIONS = DATA / "fig20-build-table.actions.json"
PLAN = DATA / "build-table.plan.json"
TRACE = ROOT / "lbw_engine" / "data" / "build-table.trace.jsonl"
HUGE = "9" * 400


def _replace(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


# -- input builders: each writes into the case folder and returns the argv --------


def rules(file: str, edit: Callable[[bytes], bytes] | None, remove: bool = False):
    """``lbw check`` on a copy of rules/ with one file edited (or removed)."""
    def build(tmp: Path) -> list[str]:
        folder = tmp / "rules"
        shutil.copytree(ROOT / "rules", folder, ignore=shutil.ignore_patterns("__pycache__"))
        if remove:
            (folder / file).unlink()
        else:
            (folder / file).write_bytes(edit((folder / file).read_bytes()))
        return ["check", str(folder)]
    return build


def text(edit: Callable[[str], str]) -> Callable[[bytes], bytes]:
    """A text edit as a byte edit."""
    return lambda data: edit(data.decode()).encode()


def scenario(edit: Callable[[str], str]):
    """``lbw watch`` on an edited build-table scenario (stopped after the loader)."""
    def build(tmp: Path) -> list[str]:
        path = tmp / "scenario.yaml"
        path.write_text(edit(SCENARIO.read_text()))
        return ["watch", str(path), "--out", str(tmp / "out")]
    return build


def raw(command: str, name: str, content: str | bytes):
    """``lbw analyze`` / ``lbw execute`` on a file of the given content."""
    def build(tmp: Path) -> list[str]:
        path = tmp / name
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
        if command == "execute":
            return ["execute", str(path), str(SCENARIO), "--out", str(tmp / "out")]
        return ["analyze", str(path), "--out", str(tmp / "out")]
    return build


def trace(edit: Callable[[str], str]):
    """``lbw recognize`` on an edited copy of the bundled event trace."""
    def build(tmp: Path) -> list[str]:
        path = tmp / "trace.jsonl"
        path.write_text(edit(TRACE.read_text()))
        return ["recognize", str(path), "--out", str(tmp / "out")]
    return build


def actions(edit: Callable[[dict], None]):
    doc = json.loads(ACTIONS.read_text())
    edit(doc)
    return raw("analyze", "actions.json", json.dumps(doc))


def plan(edit: Callable[[dict], None]):
    doc = json.loads(PLAN.read_text())
    edit(doc)
    return raw("execute", "plan.json", json.dumps(doc))


DEEP_YAML = "[" * 1000 + "]" * 1000
DEEP_JSON = '{"operations": ' + "[" * 100000 + "]" * 100000 + "}"
DEEP_PLAN = '{"root": "b", "operators": ' + "[" * 100000 + "]" * 100000 + "}"

# (cause, input, expected exit, message fragment); the ids name the issue's rows.
ROWS = [
    ("table1-RecursionError-yaml-scenario",
     scenario(lambda t: _replace(t, "brick: [30, 30, 50]", f"brick: {DEEP_YAML}")),
     2, "nested more than 100 levels deep"),
    ("table1-RecursionError-yaml-rule-file",
     rules("motions.yaml", text(lambda t: t + f"\ndeep: {DEEP_YAML}\n")),
     2, "nested more than 100 levels deep"),
    ("table2-RecursionError-json-actions", raw("analyze", "actions.json", DEEP_JSON),
     2, "nested more than 100 levels deep"),
    ("table2-RecursionError-json-plan", raw("execute", "plan.json", DEEP_PLAN),
     2, "nested more than 100 levels deep"),
    ("table3-re.error-templates.lark",
     rules("templates.lark", text(lambda t: _replace(t, '_withdraw: "WITHDRAW"',
                                                     '_withdraw: "WITHDRAW" | /[/'))),
     2, "the regular expression /[/ does not compile"),
    ("table4-UnicodeDecodeError-templates.lark", rules("templates.lark", lambda b: b + b"\xff\n"),
     2, "not UTF-8 text: byte 0xff"),
    ("table5-OverflowError-rule-number",
     rules("commands.yaml", text(lambda t: _replace(t, "approach-height: 200.0",
                                                    f"approach-height: {HUGE}"))),
     2, "an integer of 400 digits"),
    ("table5-OverflowError-scenario-number",
     scenario(lambda t: _replace(t, "brick: [30, 30, 50]", f"brick: [{HUGE}, 30, 50]")),
     2, "an integer of 400 digits"),
    ("table6-TypeError-shape-list",
     scenario(lambda t: _replace(t, "{shape: brick, at: [-210, 70]}",
                                 "{shape: [], at: [-210, 70]}")),
     2, "unknown shape []"),
    ("table7-attention-region-unbounded",
     rules("constants.yaml", text(lambda t: _replace(t, "attention-region: [50, 50, 45]",
                                                     "attention-region: [1.0e+30, 50, 45]"))),
     2, "attention-region[0]: expected a number in [5, 300]"),
    ("extra-alias-bomb-refused",
     scenario(lambda t: _replace(t, "brick: [30, 30, 50]", f"brick: {bomb(9)}")),
     2, "aliases (an alias bomb?)"),
    ("extra-alias-bomb-message-shortened",
     scenario(lambda t: _replace(t, "brick: [30, 30, 50]", f"brick: {bomb(4)}")),
     2, "shapes.brick: expected a list of 3 numbers, got [[[[[1, 1, 1, 1, 1, 1, 1, 1, 1], [1,"),
    ("extra-control-character-one-line",
     scenario(lambda t: _replace(t, "name: build-table", "name: build\x01table")),
     2, "scenario.yaml:5: control character U+0001 at column 12"),
    ("extra-plot.lark-missing", rules("plot.lark", None, remove=True),
     2, "plot.lark: the plot grammar is missing"),
    ("extra-plot.lark-empty", rules("plot.lark", lambda b: b""), 2, "bad plot grammar"),
    ("extra-plot.lark-random-bytes", rules("plot.lark", lambda b: bytes(range(7, 200))),
     2, "plot.lark:2: not UTF-8 text: byte 0x80 at column 118"),
    ("extra-plot.lark-cannot-read-plan.txt",
     rules("plot.lark", text(lambda t: _replace(t, '":sc-plus" relations',
                                                '":sc_plus" relations'))),
     2, "does not read back the plot notation"),
    ("extra-ends-holding-actions",
     actions(lambda d: d.update(operations=d["operations"][:18])),
     2, "operations[17].final_state.relations: the demonstration ends with hand holding plate"),
    ("extra-ends-holding-scenario",
     scenario(lambda t: t[:t.rindex("    - place: plate1")]),
     2, "the demonstration ends with 'plate1' in the hand"),
    ("extra-unknown-key-actions",
     actions(lambda d: d["operations"][3].update(colour="red")),
     2, "operations[3].colour: unknown key 'colour'"),
    ("extra-unknown-key-actions-top", actions(lambda d: d.update(comment="x")),
     2, "comment: unknown key 'comment'"),
    ("extra-unknown-key-plan",
     plan(lambda d: d["operators"]["build02"].update(colour="red")),
     2, "operators.build02.colour: unknown key 'colour'"),
    ("extra-unknown-key-plan-top", plan(lambda d: d.update(version=2)),
     2, "version: unknown key 'version'"),
    ("extra-gripper-finger-negative-zero",
     rules("commands.yaml", text(lambda t: _replace(t, "finger: [10.0, 20.0, 50.0]",
                                                    "finger: [10.0, -0.0, 50.0]"))),
     2, "gripper.finger[1]: expected a number in [1, 200], got -0"),
    # Found by `python -m bench fuzz --count 10000` (seed 1) after the fixes above.
    ("fuzz-effects-move-number",
     rules("effects.yaml", text(lambda t: _replace(t, "move: {follow: $hand,",
                                                   "move: {follow: 0.5,"))),
     2, "0.5 is neither a variable ($name) nor '*'"),
    ("fuzz-events-detector-mapping",
     rules("events.yaml", text(lambda t: _replace(t, "detector: motion-detector",
                                                  "detector: {a: 1}"))),
     2, "detector {'a': 1} does not exist"),
    ("fuzz-transition-next-list",
     rules("transitions.yaml", text(lambda t: _replace(t, "next: Task,", "next: [x],"))),
     2, "Table VII row 'next' must be a name, got ['x']"),
    ("fuzz-rotation-overflow-warning",  # numpy's overflow warning made it three lines
     rules("commands.yaml", text(lambda t: _replace(t, "- [0.906308, 0.422618, 0.0]",
                                                    "- [0.906308, 1.0e+300, 0.0]"))),
     2, "arm-frame.rotation[0][1]: expected a number in [-1, 1], got 1e+300"),
    ("fuzz-trace-positions-string",
     trace(lambda t: _replace(t, '"positions": {"hand": [250.0, 350.0, 200.0]}',
                              '"positions": ""')),
     2, "trace.jsonl:3: 'positions' must map names to [x, y, z]"),
]


@pytest.mark.parametrize("build,code,fragment", [r[1:] for r in ROWS], ids=[r[0] for r in ROWS])
def test_issue15_row(tmp_path, build, code, fragment):
    argv = build(tmp_path)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*") if p.is_file())
    run = run_lbw(argv)
    assert not run.traceback and not run.internal, run.stderr
    assert run.code == code, run.stderr
    assert len(run.stderr.splitlines()) == 1, run.stderr
    assert fragment in run.stderr, run.stderr
    assert len(run.stderr) < 400, run.stderr
    after = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*") if p.is_file())
    assert after == before  # a rejection writes nothing


def test_bundled_rules_and_inputs_still_pass(tmp_path):
    """The guard refuses nothing the project ships."""
    assert run_lbw(["check"]).code == 0
    assert run_lbw(["analyze", str(ACTIONS), "--out", str(tmp_path / "a")]).code == 0
    for path in sorted((ROOT / "scenarios").glob("*.yaml")):  # stopped after the loader
        run = run_lbw(["watch", str(path), "--out", str(tmp_path / "w")])
        assert run.code == 1 and "stopped after the scenario loader" in run.stderr, run.stderr


SHORTEN = [  # (value, expected text or prefix) — values printed in messages
    ("brick", "'brick'"),
    (10**400, "<an integer of about 401 digits>"),
    ("x" * 500, "'" + "x" * 78 + "…"),
    (loads(f"a: {bomb(3)}")["a"],
     "[[[[1, 1, 1, 1, 1, 1, 1, 1, 1], [1, 1, 1, 1, 1, 1, 1, 1, 1], [1, 1, 1, 1, 1, 1,…"),
    ({"k": "line\nbreak"}, "{'k': 'line\\nbreak'}"),
]


@pytest.mark.parametrize("value,expected", SHORTEN, ids=["name", "huge-int", "long-string",
                                                          "alias-bomb", "newline"])
def test_shorten(value, expected):
    assert shorten(value) == expected


def _unreadable(path: Path, monkeypatch) -> None:
    """Root reads every file, so a permission error is simulated."""
    def refuse(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr(Path, "open", refuse)


READ = [  # (case, file content or None, set-up, message fragment) for guard.read_text
    ("missing", None, None, "x.json: file not found"),
    ("unreadable", b"{}", _unreadable, "cannot read the file: permission denied"),
    ("too-large", b"[" + b"0," * 40 + b"0]", "limit", "larger than 0 MB, the most lbw reads"),
    ("bad-utf8-line", b'{"a":\n "\xc3\x28"}', None, "x.json:2: not UTF-8 text: byte 0xc3"),
]


@pytest.mark.parametrize("content,setup,fragment", [r[1:] for r in READ],
                         ids=[r[0] for r in READ])
def test_read_text_errors(tmp_path, monkeypatch, content, setup, fragment):
    from lbw_engine import guard
    from lbw_engine.errors import InputError

    path = tmp_path / "x.json"
    if content is not None:
        path.write_bytes(content)
    if setup == "limit":
        monkeypatch.setattr(guard, "MAX_BYTES", 16)
    elif setup is not None:
        setup(path, monkeypatch)
    with pytest.raises(InputError) as info:
        guard.read_text(path)
    assert fragment in str(info.value)


JSON = [  # (case, JSON text, message fragment) for guard.json_document
    ("NaN", '{"a": NaN}', "NaN is not a number; expected a finite number"),
    ("overflowing-float", '{"a": [1,\n 1e999]}', ":2: the number 1e999 is too large"),
    ("long-integer", '{"a": ' + "9" * 5000 + "}", "an integer of 5000 digits; expected at most 18"),
    ("duplicate-key", '{"a": 1, "a": 2}', "duplicate key 'a' in one object"),
    ("101-deep", "[" * 101 + "]" * 101, "nested more than 100 levels deep"),
    ("syntax", '{"a": }', "invalid JSON: Expecting value at column 7"),
]


@pytest.mark.parametrize("text,fragment", [r[1:] for r in JSON], ids=[r[0] for r in JSON])
def test_json_document_errors(text, fragment):
    from lbw_engine.errors import InputError
    from lbw_engine.guard import json_document

    with pytest.raises(InputError) as info:
        json_document(text, "x.json")
    assert fragment in str(info.value)
