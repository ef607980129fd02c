"""Recognition repair end to end (docs/repair.md): a slip injected into the recognizer's
output (a carry cut in two by a spurious NO-OP over the table, as bench seeds 1014,
1026 and 1095 show at 4x noise) is repaired by `lbw run`; the run passes, actions.json
records the change, execution.json keeps the raw comparison beside the repaired one.
`lbw analyze` repairs a hand-written file only when asked."""

import copy
import json
from pathlib import Path

from lbw_engine.cli import main
from lbw_engine.pipeline import run as runmod

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios" / "place-and-align.yaml"
FIG12 = ROOT / "tests" / "data" / "fig12-inverted-arch.actions.json"


def cut_first_carry(actions):
    """The first REACH-WITH-OBJ as two, with a NO-OP over the table between them."""
    ops = actions["operations"]
    k = next(i for i, op in enumerate(ops) if op["operation"] == "REACH-WITH-OBJ")
    carry = ops[k]
    first = dict(copy.deepcopy(carry), name="reach-with-obj09", target=["table"])
    touch = dict(copy.deepcopy(carry), name="no09", operation="NO-OP", target=["table"],
                 final_state=copy.deepcopy(carry["initial_state"]), fine=[])
    return {**actions, "operations": [*ops[:k], first, touch, *ops[k:]]}


def test_lbw_run_repairs_a_slip_and_passes(tmp_path, monkeypatch, capsys):
    real = runmod.to_actions
    monkeypatch.setattr(runmod, "to_actions", lambda rec: cut_first_carry(real(rec)))
    assert main(["run", str(SCENARIO), "--out", str(tmp_path)]) == 0
    actions = json.loads((tmp_path / "actions.json").read_text())
    (fix,) = actions["repairs"]
    assert [w["name"] for w in fix["was"]] == ["reach-with-obj09", "no09", "reach-with-obj01"]
    assert [n["operation"] for n in fix["now"]] == ["REACH-WITH-OBJ"]
    verdict = json.loads((tmp_path / "execution.json").read_text())
    rec = verdict["recognition"]
    assert not rec["exact"] and "NO-OP" in rec["recognized"]  # the raw comparison is kept
    assert rec["repair"]["exact"] and rec["repair"]["repairs"] == 1
    assert rec["repair"]["recognized"] == rec["expected"]
    assert verdict["success"] and verdict["failure"] is None
    out = capsys.readouterr().out
    assert "as demonstrated after 1 repair(s)" in out and "repaired at #2" in out


def test_lbw_analyze_repairs_only_when_asked(tmp_path, capsys):
    doc = cut_first_carry(json.loads(FIG12.read_text()))
    slipped = tmp_path / "in" / "actions.json"
    slipped.parent.mkdir()
    slipped.write_text(json.dumps(doc))
    assert main(["analyze", str(slipped), "--out", str(tmp_path / "plain")]) == 0
    assert not (tmp_path / "plain" / "actions.json").exists()
    plain = json.loads((tmp_path / "plain" / "plan.json").read_text())
    assert any(op["class"] == "FAKE" for op in plain["operators"].values())  # learned as seen
    assert main(["analyze", str(slipped), "--out", str(tmp_path / "fixed"), "--repair"]) == 0
    fixed = json.loads((tmp_path / "fixed" / "actions.json").read_text())
    assert len(fixed["repairs"]) == 1
    plan = json.loads((tmp_path / "fixed" / "plan.json").read_text())
    assert not any(op["class"] == "FAKE" for op in plan["operators"].values())
    assert "lbw analyze: repaired at #2" in capsys.readouterr().out


def test_lbw_analyze_repair_never_overwrites_its_input(tmp_path, capsys):
    slipped = tmp_path / "actions.json"
    slipped.write_text(json.dumps(cut_first_carry(json.loads(FIG12.read_text()))))
    assert main(["analyze", str(slipped), "--repair"]) == 2
    err = capsys.readouterr().err
    assert "--repair writes DIR/actions.json, which is ACTIONS.json itself" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["actions.json"]
