"""docs/adding-an-operation.md, executed: rule edits add PICK-FROM-BLOCK end to end.

The edits below must appear verbatim in the tutorial, so the document and
this test cannot drift apart: Table V (operations.yaml), its effect
(effects.yaml), the plan templates (templates.lark) and the command expansion
(commands.yaml). Then ``lbw run`` on the bundled disassembly demonstration
must pass with PICK-FROM-BLOCK recognized, planned, expanded and verified."""

import json
import shutil
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.paths import default_rules_dir

ROOT = Path(__file__).resolve().parents[2]
TUTORIAL = (ROOT / "docs" / "adding-an-operation.md").read_text()
TRACE = ROOT / "tests" / "data" / "traces" / "pick-from-block.jsonl"

FEATURE = """  source-kind:
    source: support-kind
    kinds: {Table: table, Loc: block}
"""
ROW = "    - {when: {sil-diff: decreased, source-kind: block}, operation: PICK-FROM-BLOCK}\n"
EFFECT = """  PICK-FROM-BLOCK:
    bind: {hand: base, object: {nearest: target, to: sil-diff}}
    remove:
      - [on, $object, "*"]
      - [on-multiple, $object, "*"]
      - [co-support, "*", $object]
    add:
      - [holding, $hand, $object]
      - [held-by, $object, $hand]
    move: {follow: $hand, object: $object}
"""
PICK_ROW = "    - {when: {sil-diff: decreased}, operation: PICK}\n"
FETCH = 'fetch: "REACH" "PICK" _withdraw*'
TEMPLATE = 'fetch: "REACH" ("PICK" | "PICK-FROM-BLOCK") _withdraw*'
PICK_COMMAND = "  PICK:           {goal: [object], steps: [[PICK, goal]], check-jaws: true}\n"
COMMAND = "  PICK-FROM-BLOCK: {goal: [object], steps: [[PICK, goal]], check-jaws: true}\n"


def edited_copy(tmp_path: Path, row_first: bool = True) -> Path:
    copy = tmp_path / "my-rules"
    shutil.copytree(default_rules_dir(), copy)
    ops = (copy / "operations.yaml").read_text()
    ops = ops.replace("features:\n", "features:\n" + FEATURE, 1)
    ops = ops.replace(PICK_ROW, ROW + PICK_ROW if row_first else PICK_ROW + ROW, 1)
    (copy / "operations.yaml").write_text(ops)
    effects = (copy / "effects.yaml").read_text()
    (copy / "effects.yaml").write_text(effects.replace("operations:\n", "operations:\n" + EFFECT))
    templates = (copy / "templates.lark").read_text()
    assert FETCH in templates
    (copy / "templates.lark").write_text(templates.replace(FETCH, TEMPLATE))
    commands = (copy / "commands.yaml").read_text()
    assert PICK_COMMAND in commands
    (copy / "commands.yaml").write_text(commands.replace(PICK_COMMAND, PICK_COMMAND + COMMAND))
    return copy


@pytest.mark.parametrize("snippet", [FEATURE, ROW, EFFECT, TEMPLATE, COMMAND],
                         ids=["feature", "row", "effect", "template", "command"])
def test_tutorial_shows_the_edit(snippet):
    assert snippet in TUTORIAL


def recognized(tmp_path, rules_args):
    out = tmp_path / "out"
    assert main(["recognize", str(TRACE), "--out", str(out), *rules_args]) == 0
    return [op["operation"] for op in json.loads((out / "actions.json").read_text())["operations"]]


def test_bundled_rules_report_a_plain_pick(tmp_path):
    assert recognized(tmp_path, []) == [
        "REACH", "PICK", "REACH-WITH-OBJ", "PLACE-ON-TABLE", "WITHDRAW"]


def test_edited_copy_reports_the_new_operation(tmp_path, capsys):
    copy = edited_copy(tmp_path)
    assert main(["check", str(copy)]) == 0
    ops = recognized(tmp_path, ["--rules", str(copy)])
    assert ops == ["REACH", "PICK-FROM-BLOCK", "REACH-WITH-OBJ", "PLACE-ON-TABLE", "WITHDRAW"]
    out = tmp_path / "out" / "actions.json"
    pick = json.loads(out.read_text())["operations"][1]
    assert pick["name"] == "pick-from-block01"
    assert ["holding", "hand", "brick2"] in pick["final_state"]["relations"]


def test_edited_copy_keeps_picks_from_the_table(tmp_path):
    copy = edited_copy(tmp_path)
    rec_out = tmp_path / "fig20"
    trace = ROOT / "tests" / "data" / "traces" / "fig20-build-table.jsonl"
    assert main(["recognize", str(trace), "--out", str(rec_out), "--rules", str(copy)]) == 0
    data = json.loads((rec_out / "actions.json").read_text())
    ops = [op["operation"] for op in data["operations"]]
    assert ops.count("PICK") == 5 and "PICK-FROM-BLOCK" not in ops


def test_row_after_pick_is_refused(tmp_path, capsys):
    copy = edited_copy(tmp_path, row_first=False)
    assert main(["check", str(copy)]) == 2
    assert "can never fire" in capsys.readouterr().err


def test_the_tutorial_runs_end_to_end_on_a_disassembly(tmp_path):
    """lbw run on scenarios/unstack.yaml (a brick taken off a cube and put elsewhere)."""
    copy = edited_copy(tmp_path)
    out = tmp_path / "unstack"
    assert main(["run", str(ROOT / "scenarios" / "unstack.yaml"), "--out", str(out),
                 "--rules", str(copy)]) == 0
    ops = [op["operation"] for op in json.loads((out / "actions.json").read_text())["operations"]]
    assert "PICK-FROM-BLOCK" in ops and "PICK" not in ops
    assert "<pick-from-block>" in (out / "commands.txt").read_text()
    verdict = json.loads((out / "execution.json").read_text())
    assert verdict["success"] is True and verdict["failure"] is None
