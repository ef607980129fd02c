"""Fig. 10 and Sec. V-A, Cases 1 and 2: the recognizer before and after an event
arrives during a Transfer that carries a block (Transfer2, after a PICK).

Case 1: only :Near -> Transfer2 ends as REACH-WITH-OBJ, LocalMotion2 begins,
the stack's upper level holds LocalMotion's initial attention, and the
change-detector takes its first snapshot.
Case 2: :Found-moving (with or without :Near) -> Transfer2 ends as WITHDRAW,
Transfer3 begins, the Transfer level is reset to :Small-motion and the
:Disappeared node is replaced by a new one.
"""

import dataclasses

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.replay import run_script

RULES = load_rules()
ONE_PASS = dataclasses.replace(RULES, constants={**RULES.constants, "detect-passes-per-frame": 1})
B = {"shape": "brick", "size": [30, 30, 50]}
LOCATE = [{"event": "loc-exist", "found": ["loc1", "loc2"], "objects": {
    "loc1": {**B, "position": [0, 200, 25]}, "loc2": {**B, "position": [100, 200, 25]}}}]
ENTER = [{"event": "found-moving", "found": ["hand"], "positions": {"hand": [0, 300, 200]}}]
DOWN = [{"event": "small-motion", "value": "moving-down"}]
BEFORE = [LOCATE, ENTER, DOWN, [{"event": "near", "found": ["loc1"]}],
          [{"event": "far"}, {"detector": "change-detector", "value": "decreased"}], DOWN]
W, H = ("world",), ("hand",)
FM, DA, SM = ("found-moving", W, H), ("disappeared", W, H), ("small-motion", H, ())
NEAR = {"event": "near", "found": ["loc2"]}
MOVING = {"event": "found-moving", "found": ["hand"]}


def test_before_state():
    rec = run_script(ONE_PASS, BEFORE)
    transfer = rec.root.subnode
    assert (transfer.name, transfer.base, transfer.special) == ("Transfer2", H, ("loc1",))
    assert [n.operation for n in rec.root.history] == ["REACH", "PICK"]
    assert rec.stack.describe() == [[FM, DA], [SM, ("near", H, ())]]


def test_case1_only_near():
    rec = run_script(ONE_PASS, [*BEFORE, [NEAR]])
    ended = rec.root.history[-1]
    assert (ended.name, ended.operation, ended.final_event) == (
        "Transfer2", "REACH-WITH-OBJ", "near")
    local = rec.root.subnode
    assert (local.name, local.base, local.target, local.special) == (
        "LocalMotion2", H, ("loc2",), ("loc1",))
    assert rec.stack.describe() == [
        [FM, DA],
        [("large-motion", H, ()), ("far", H, ("loc2",)), ("true", H, ())],
    ]
    assert "change-detector" in local.snapshots  # the initial snapshot is taken
    assert local.initial_state.positions["loc1"]  # IS copies base, target and special


@pytest.mark.parametrize("frame", [[MOVING], [MOVING, NEAR]],
                         ids=["Case2-found-moving", "Case2-found-moving-with-near"])
def test_case2_found_moving(frame):
    before = run_script(ONE_PASS, BEFORE)
    old_da = before.stack.levels[0][1]
    rec = run_script(ONE_PASS, [*BEFORE, frame])
    ended = rec.root.history[-1]
    assert (ended.name, ended.operation, ended.final_event) == (
        "Transfer2", "WITHDRAW", "found-moving")
    new = rec.root.subnode
    assert (new.name, new.base, new.target) == ("Transfer3", H, ())
    assert rec.stack.describe() == [[FM, DA], [SM]]
    assert rec.stack.levels[0][1] is not old_da  # "the DA is replaced by a new one"
    assert all(n.motion != "LocalMotion" or n.name != "LocalMotion2" for n in rec.root.history)
