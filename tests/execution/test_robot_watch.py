"""The robot watched by the demonstration's recognizer (issue #13 item 2, Sec. IX-C2).

A table of the operation comparison (lbw_engine.do.opcheck), then the monitored
execution end to end: the bundled unstack plan executed without faults, where
the gripper's recognized operations must agree with the executed ones, and
with a drop during the transfer, which the comparison must report.
"""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.do.opcheck import Op, differences, moving_operations
from lbw_engine.paths import bundled_scenario
from lbw_engine.rules import load_rules

DATA = Path(__file__).resolve().parent.parent / "data"

P, T, B = Op("PICK", "a"), Op("PLACE-ON-TABLE", "a"), Op("PLACE-ON-BLOCK", "b")

# executed, recognized, expected differences as (object, expected, observed)
CASES = [
    pytest.param([P, T], [P, T], [], id="same"),
    pytest.param([P, T], [P], [("a", "PLACE-ON-TABLE a", None)], id="missing-place"),
    pytest.param([P, T], [P, T, Op("PICK", "c")], [("c", None, "PICK c")], id="extra-op"),
    pytest.param([P, T], [P, Op("PLACE-ON-TABLE", "c")],
                 [("a", "PLACE-ON-TABLE a", "PLACE-ON-TABLE c")], id="wrong-object"),
    pytest.param([P, B], [P, Op("PLACE-ON-TABLE", "b")],
                 [("b", "PLACE-ON-BLOCK b", "PLACE-ON-TABLE b")], id="other-operation"),
    pytest.param([P, T], [], [("a", "PICK a", None), ("a", "PLACE-ON-TABLE a", None)],
                 id="nothing-seen"),
]


@pytest.mark.parametrize("executed,recognized,expected", CASES)
def test_differences(executed, recognized, expected):
    got = [(d["object"], d["expected"], d["observed"]) for d in differences(executed, recognized)]
    assert got == expected


def test_the_compared_operations_are_those_whose_effect_moves_an_object():
    rules = load_rules()
    moving = moving_operations(rules.effects)
    assert set(moving) == {op for op, r in rules.effects.items() if r.move}
    assert moving and all(f"${var}" in rules.effects[op].move.values()
                          for op, var in moving.items())


def execute(tmp_path, scenario, capsys):
    out = tmp_path / "out"
    code = main(["execute", str(DATA / "unstack.plan.json"), str(scenario), "--out", str(out)])
    err = capsys.readouterr().err
    return code, json.loads((out / "execution.json").read_text()), err


def test_fault_free_robot_operations_are_recognized_as_executed(tmp_path, capsys):
    code, report, err = execute(tmp_path, bundled_scenario("unstack"), capsys)
    assert code == 0, err
    ops = report["monitor"]["operations"]
    assert [o["operator"] for o in ops] == ["achieve01"]
    moved = ops[0]["moving"]
    assert moved["executed"] == ["PICK top1", "PLACE-ON-TABLE top1"]
    assert moved["recognized"] == moved["executed"] and ops[0]["agree"] is True
    # the whole executed sequence is recognized in order (the step aside comes after it)
    assert ops[0]["recognized"][:len(ops[0]["executed"])] == ops[0]["executed"]
    assert report["monitor"]["detections"] == []


def test_a_drop_is_seen_in_the_robot_operations(tmp_path, capsys):
    text = bundled_scenario("unstack").read_text().rstrip("\n") + "\n"
    path = tmp_path / "drop.yaml"
    path.write_text(text + "  faults:\n    - {during: 1, kind: drop}\n")
    code, report, err = execute(tmp_path, path, capsys)
    assert [f["kind"] for f in report["faults"]] == ["drop"]
    first = report["monitor"]["operations"][0]
    assert first["operator"] == "achieve01" and first["agree"] is False
    seen = [d for d in report["monitor"]["detections"] if d["kind"] == "operation"]
    assert seen and seen[0]["operator"] == "achieve01" and seen[0]["object"] == "top1"
    assert seen[0]["expected"] == "PLACE-ON-TABLE top1"
    assert seen[0]["t"] >= report["faults"][0]["t"]
