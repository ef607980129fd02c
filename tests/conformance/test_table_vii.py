"""Table VII, one case per row: an event received by an ACT-node of a motion class
leads to the listed transition and to a next ACT-node with the listed base/target.

Each case drives the real recognizer with scripted detector answers (one list
of records per frame) and looks at the action model afterwards.
"""

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.replay import run_script

RULES = load_rules()
B1 = {"shape": "brick", "size": [30, 30, 50], "position": [0, 200, 25]}
B2 = {"shape": "brick", "size": [30, 30, 50], "position": [100, 200, 25]}
LOCATE = [{"event": "loc-exist", "found": ["b1", "b2"], "objects": {"b1": B1, "b2": B2}}]
ENTER = [{"event": "found-moving", "found": ["hand"], "positions": {"hand": [0, 300, 200]}}]
DOWN = [{"event": "small-motion", "value": "moving-down"}]
NEAR_B1 = [{"event": "near", "found": ["b1"]}]
TO_LOCAL = [LOCATE, ENTER, DOWN, NEAR_B1]  # a LocalMotion on b1 with an empty hand
PICKED = [*TO_LOCAL, [{"event": "far"}, {"detector": "change-detector", "value": "decreased"}]]
HOLDING_NEAR_B2 = [*PICKED, DOWN, [{"event": "near", "found": ["b2"]}]]


def active(rec, level):
    """The ACT-node currently recognized at a stack level."""
    node = rec.root
    for _ in range(level):
        node = node.subnode
    return node


def only_root_task(rec):
    assert rec.root.motion == "Task" and rec.root.base == ("world",)
    assert rec.root.target == ()


def loc_exist_sets_target(rec):
    assert rec.root.target == ("b1", "b2") and rec.root.subnode is None
    assert rec.root.history == []  # no transition: a perceptual action only


def found_moving_down_transfer(rec):
    sub = rec.root.subnode
    assert (sub.motion, sub.base, sub.target, sub.initial_event) == (
        "Transfer", ("hand",), (), "found-moving")


def disappeared_up(rec):
    assert rec.finished and rec.root.final_event == "disappeared"
    assert rec.root.subnode is None
    assert [n.motion for n in rec.root.history] == ["Transfer"]


def near_next_local_motion(rec):
    sub = rec.root.subnode
    assert (sub.motion, sub.base, sub.target) == ("LocalMotion", ("hand",), ("b1",))
    ended = rec.root.history[-1]
    assert (ended.motion, ended.final_event, ended.target) == ("Transfer", "near", ("b1",))


def true_down_approach_empty_hand(rec):
    sub = active(rec, 2)
    assert (sub.motion, sub.base, sub.target) == ("Approach", ("hand",), ("b1",))
    assert active(rec, 1).motion == "LocalMotion"


def true_down_approach_holding(rec):
    sub = active(rec, 2)
    assert (sub.motion, sub.base, sub.target) == ("Approach", ("b1",), ("b2",))
    assert active(rec, 1).special == ("b1",)


def far_next_transfer(rec):
    sub = active(rec, 1)
    assert (sub.motion, sub.base, sub.target, sub.initial_event) == (
        "Transfer", ("hand",), (), "far")
    assert rec.root.history[-1].motion == "LocalMotion"
    assert sub.special == ("b1",)  # the picked block, now held


def join_next_fine_motion(rec):
    sub = active(rec, 2)
    assert (sub.motion, sub.base, sub.target, sub.initial_event) == (
        "FineMotion", ("hand",), ("b1",), "join")
    assert active(rec, 1).history[-1].motion in ("Approach", "Depart")


def split_next_depart(rec):
    sub = active(rec, 2)
    assert (sub.motion, sub.base, sub.target) == ("Depart", ("hand",), ("b1",))
    assert active(rec, 1).history[-1].motion == "FineMotion"


ROWS = [  # (case id, motion, event, frames, check)
    ("TableVII-row1-ColdBoot-true", "ColdBoot", "true", [], only_root_task),
    ("TableVII-row2-Task-loc-exist", "Task", "loc-exist", [LOCATE], loc_exist_sets_target),
    ("TableVII-row3-Task-found-moving", "Task", "found-moving", [LOCATE, ENTER],
     found_moving_down_transfer),
    ("TableVII-row4-Task-disappeared", "Task", "disappeared",
     [LOCATE, ENTER, [{"event": "disappeared"}]], disappeared_up),
    ("TableVII-row5-Transfer-near", "Transfer", "near", TO_LOCAL, near_next_local_motion),
    ("TableVII-row6a-LocalMotion-true-base", "LocalMotion", "true", TO_LOCAL,
     true_down_approach_empty_hand),
    ("TableVII-row6b-LocalMotion-true-special", "LocalMotion", "true", HOLDING_NEAR_B2,
     true_down_approach_holding),
    ("TableVII-row7-LocalMotion-far", "LocalMotion", "far", PICKED, far_next_transfer),
    ("TableVII-row8-Approach-join", "Approach", "join", [*TO_LOCAL, [{"event": "join"}]],
     join_next_fine_motion),
    ("TableVII-row9-Depart-join", "Depart", "join",
     [*TO_LOCAL, [{"event": "join"}], [{"event": "split"}], [{"event": "join"}]],
     join_next_fine_motion),
    ("TableVII-row10-FineMotion-split", "FineMotion", "split",
     [*TO_LOCAL, [{"event": "join"}], [{"event": "split"}]], split_next_depart),
]


@pytest.mark.parametrize("frames,check", [r[3:] for r in ROWS], ids=[r[0] for r in ROWS])
def test_table_vii_row(frames, check):
    rec = run_script(RULES, frames)
    check(rec)


def test_every_rule_row_is_covered():
    """The rules have exactly the rows this table tests (no untested transition)."""
    assert set(RULES.transitions) == {(r[1], r[2]) for r in ROWS}
