"""Table VIII, one case per row: the attention redirection a motion class makes on
an event (or on creation, ":Init") shows on the attention stack.

Stack levels are listed as (event, base, target) per ATTN-node. To see a node
that a later pass of the same frame would consume at once (LocalMotion's
":True"), these cases run one detect pass per frame.
"""

import dataclasses

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.detectors import DetectorRegistry
from lbw_engine.see.recognizer import Recognizer
from lbw_engine.see.replay import run_script

RULES = load_rules()
ONE_PASS = dataclasses.replace(RULES, constants={**RULES.constants, "detect-passes-per-frame": 1})
B1 = {"shape": "brick", "size": [30, 30, 50], "position": [0, 200, 25]}
LOCATE = [{"event": "loc-exist", "found": ["b1"], "objects": {"b1": B1}}]
ENTER = [{"event": "found-moving", "found": ["hand"], "positions": {"hand": [0, 300, 200]}}]
DOWN = [{"event": "small-motion", "value": "moving-down"}]
STAY = [{"event": "small-motion", "velocity": [1.0, 2.0, 0.0]}]  # 2.2 mm/s: :Staying
NEAR = [{"event": "near", "found": ["b1"]}]
JOIN, SPLIT = [{"event": "join"}], [{"event": "split"}]
W, H, B = ("world",), ("hand",), ("b1",)
FM, DA = ("found-moving", W, H), ("disappeared", W, H)
SM = ("small-motion", H, ())
LM, FR, TR = ("large-motion", H, ()), ("far", H, B), ("true", H, ())


def cold_boot(rules):
    """A recognizer before its first frame."""
    return Recognizer(rules, DetectorRegistry.for_rules(rules, {
        name: None for name in rules.detectors}))


ROWS = [  # (case id, (motion, on, op, event), rules, frames, level, expected level contents)
    ("TableVIII-row0-ColdBoot-init", ("ColdBoot", "init", "add", "true"), RULES, None, 0,
     [("true", W, ())]),
    ("TableVIII-row1-Task-init", ("Task", "init", "add", "loc-exist"), RULES, [], 0,
     [("loc-exist", W, ())]),
    ("TableVIII-row2-Task-loc-exist", ("Task", "loc-exist", "reset", "found-moving"), RULES,
     [LOCATE], 0, [FM]),
    ("TableVIII-row3-Task-found-moving", ("Task", "found-moving", "add", "disappeared"), RULES,
     [LOCATE, ENTER], 0, [FM, DA]),
    ("TableVIII-row4-Transfer-init", ("Transfer", "init", "add", "small-motion"), RULES,
     [LOCATE, ENTER], 1, [SM]),
    ("TableVIII-row5-Transfer-staying", ("Transfer", "staying", "add", "near"), RULES,
     [LOCATE, ENTER, STAY], 1, [SM, ("near", H, ())]),
    ("TableVIII-row6-Transfer-moving-down", ("Transfer", "moving-down", "add", "near"), RULES,
     [LOCATE, ENTER, DOWN], 1, [SM, ("near", H, ())]),
    ("TableVIII-row7-LocalMotion-init-large-motion", ("LocalMotion", "init", "add", "large-motion"),
     ONE_PASS, [LOCATE, ENTER, DOWN, NEAR], 1, [LM, FR, TR]),
    ("TableVIII-row8-LocalMotion-init-far", ("LocalMotion", "init", "add", "far"),
     ONE_PASS, [LOCATE, ENTER, DOWN, NEAR], 1, [LM, FR, TR]),
    ("TableVIII-row9-LocalMotion-init-true", ("LocalMotion", "init", "add", "true"),
     ONE_PASS, [LOCATE, ENTER, DOWN, NEAR], 1, [LM, FR, TR]),
    ("TableVIII-row10-LocalMotion-true-delete", ("LocalMotion", "true", "delete", None),
     ONE_PASS, [LOCATE, ENTER, DOWN, NEAR, []], 1, [LM, FR]),
    ("TableVIII-row11-Approach-init", ("Approach", "init", "add", "join"), RULES,
     [LOCATE, ENTER, DOWN, NEAR], 2, [("join", H, B)]),
    ("TableVIII-row12-Depart-init", ("Depart", "init", "add", "join"), RULES,
     [LOCATE, ENTER, DOWN, NEAR, JOIN, SPLIT], 2, [("join", H, B)]),
    ("TableVIII-row13-FineMotion-init", ("FineMotion", "init", "add", "split"), RULES,
     [LOCATE, ENTER, DOWN, NEAR, JOIN], 2, [("split", H, B)]),
]


@pytest.mark.parametrize("rules,frames,level,expected", [r[2:] for r in ROWS],
                         ids=[r[0] for r in ROWS])
def test_table_viii_row(rules, frames, level, expected):
    rec = cold_boot(rules) if frames is None else run_script(rules, frames)
    stack = rec.stack.describe()
    assert stack[level] == expected


def test_lower_levels_survive_a_transition():
    """The automatic :reset on a transition pops only the new node's level and above."""
    rec = run_script(RULES, [LOCATE, ENTER, DOWN, NEAR])
    assert rec.stack.describe()[0] == [FM, DA]
    assert rec.stack.describe()[1] == [LM, FR]


def test_every_rule_row_is_covered():
    """The rules have exactly the rows this table tests."""
    rows = {(m, r.key, r.op, r.event) for m, rs in RULES.redirections.items() for r in rs}
    assert rows == {r[1] for r in ROWS}
