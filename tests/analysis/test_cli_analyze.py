"""`lbw analyze`: outputs, exit codes, no partial outputs, and analysis driven by edited rules."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.paths import default_rules_dir
from lbw_engine.understand import read_plan_text

DATA = Path(__file__).resolve().parent.parent / "data"
FIG12 = DATA / "fig12-inverted-arch.actions.json"


def test_writes_plan_json_and_txt(tmp_path, capsys):
    assert main(["analyze", str(FIG12), "--out", str(tmp_path)]) == 0
    plan = json.loads((tmp_path / "plan.json").read_text())
    assert plan["root"] == "build03"
    assert read_plan_text((tmp_path / "plan.txt").read_text()) == plan
    assert "removed: reach03 no01" in capsys.readouterr().out


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def _fig12_with(edit):
    doc = json.loads(FIG12.read_text())
    edit(doc)
    return json.dumps(doc)


BAD_INPUT = [  # (id, file text or None for missing, fragment)
    ("missing-file", None, "file not found"),
    ("bad-json", '{"operations": [', "invalid JSON"),
    ("no-operations", '{"objects": {}}', "'operations' list"),
    ("missing-key", _fig12_with(lambda d: d["operations"][3].pop("final_state")),
     "operations[3]: missing the required key 'final_state'"),
    ("bad-relation", _fig12_with(lambda d: d["operations"][1]["final_state"]["relations"]
                                 .append(["on", "x"])), "operations[1].final_state.relations[2]"),
    ("bad-at", _fig12_with(lambda d: d["operations"][3]["final_state"]["relations"][0][3]
                           .update(at=[1, 2])), "'at' must be [x, y, z]"),
    ("no-template", _fig12_with(lambda d: d["operations"].pop(2)),
     "operations[2]: no template covers PLACE-ON-TABLE here"),
    ("duplicate-name", _fig12_with(lambda d: d["operations"][1].update(name="reach01")),
     "duplicate operation name 'reach01'"),
]


@pytest.mark.parametrize("text,fragment", [b[1:] for b in BAD_INPUT], ids=[b[0] for b in BAD_INPUT])
def test_bad_input_exit_2_no_outputs(tmp_path, capsys, text, fragment):
    src = tmp_path / "in" / "actions.json"
    if text is not None:
        src.parent.mkdir()
        src.write_text(text)
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert fragment in err and str(src) in err and "Traceback" not in err
    assert not out.exists() or not any(out.iterdir())


@pytest.fixture
def rules_copy(tmp_path):
    dest = tmp_path / "rules"
    shutil.copytree(default_rules_dir(), dest)
    return dest


def test_new_operation_added_to_templates_is_accepted(tmp_path, rules_copy):
    # A user adds PICK-FROM-BLOCK to Table V (docs/adding-an-operation.md) and to
    # templates.lark; nothing else is needed for analysis.
    ops = rules_copy / "operations.yaml"
    ops.write_text(ops.read_text().replace(
        "features:\n", "features:\n  source-kind: {source: support-kind, kinds: {Loc: block}}\n"
    ).replace("    - {when: {sil-diff: decreased}, operation: PICK}\n",
              "    - {when: {sil-diff: decreased, source-kind: block},"
              " operation: PICK-FROM-BLOCK}\n"
              "    - {when: {sil-diff: decreased}, operation: PICK}\n"))
    grammar = rules_copy / "templates.lark"
    text = grammar.read_text()
    assert 'fetch: "REACH" "PICK" _withdraw*' in text
    grammar.write_text(text.replace('fetch: "REACH" "PICK" _withdraw*',
                                    'fetch: "REACH" ("PICK" | "PICK-FROM-BLOCK") _withdraw*'))
    src = _write(tmp_path, "a.json", _fig12_with(
        lambda d: d["operations"][15].update(operation="PICK-FROM-BLOCK")))
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 2  # bundled rules reject it
    assert main(["analyze", str(src), "--out", str(out), "--rules", str(rules_copy)]) == 0
    plan = json.loads((out / "plan.json").read_text())
    assert plan["operators"]["fetch04"]["plot"] == ["$sequence", ["$action", "reach05"],
                                                    ["$action", "pick04"]]


def test_grammar_may_tolerate_unknown_operations(tmp_path, rules_copy):
    grammar = rules_copy / "templates.lark"
    grammar.write_text(grammar.read_text().replace(
        "stray: fake", "stray: fake | OTHER\nOTHER: /[A-Z][A-Z-]*/"))
    src = _write(tmp_path, "a.json", _fig12_with(
        lambda d: d["operations"].insert(4, {**d["operations"][18], "name": "wave01",
                                             "operation": "WAVE"})))
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out), "--rules", str(rules_copy)]) == 0
    assert json.loads((out / "plan.json").read_text())["root"] == "build03"


BAD_RULES = [  # (id, file, old, new, fragment)
    # WITHDRAWs after a PUT could then be the PUT's or a new lead_in: shift/reduce.
    ("ambiguous-grammar", "templates.lark", "task: lead_in? (achieve | stray)*",
     "task: lead_in? (achieve | stray | lead_in)*", "bad template grammar"),
    ("grammar-syntax", "templates.lark", "achieve: fetch fake* put", "achieve: fetch (",
     "bad template grammar"),
    ("unknown-rule", "analysis.yaml", "    fake: FAKE", "    fake: FAKE\n    fetchh: FETCH",
     "does not define"),
    ("unknown-class", "analysis.yaml", "put: PUT", "put: PLACE", "'PLACE' does not exist"),
    ("unknown-pass", "analysis.yaml", "[C-T, B-T, B-S, B-T]", "[C-T, B-X]", "'B-X'"),
    ("typo-key", "analysis.yaml", "position-tolerance:", "position-tolerence:", "unknown key"),
]


@pytest.mark.parametrize("file,old,new,fragment", [b[1:] for b in BAD_RULES],
                         ids=[b[0] for b in BAD_RULES])
def test_bad_rules_exit_2(tmp_path, capsys, rules_copy, file, old, new, fragment):
    path = rules_copy / file
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    out = tmp_path / "out"
    assert main(["analyze", str(FIG12), "--out", str(out), "--rules", str(rules_copy)]) == 2
    err = capsys.readouterr().err
    assert fragment in err and file in err
    assert not out.exists() or not any(out.iterdir())
