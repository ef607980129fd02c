"""Fig. 15: sequences the templates cover (and what is removed) and ones they reject."""

from __future__ import annotations

import pytest

from lbw_engine.errors import InputError
from lbw_engine.rules import load_rules
from lbw_engine.understand import RelationTable, analyze, parse_actions


def run(words: str):
    """Analyse a sequence of bare operation names (no relations)."""
    ops = [{"operation": w, "base": ["hand"], "target": [], "special": [],
            "initial_state": {"relations": []}, "final_state": {"relations": []}}
           for w in words.split()]
    rules = load_rules().analysis
    return analyze(parse_actions({"operations": ops}, RelationTable(1.0), "t.json"), rules)


GOOD = [  # (id, sequence, top-level operators' plots of the ACHIEVE leaves, removed)
    ("Fig15-ACHIEVE=FETCH,PUT", "REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE",
     [["fetch", ["reach01", "pick01"]], ["put", ["reach-with-obj01", "place-on-table01"]]], []),
    ("Fig15-ACHIEVE=FETCH,FAKE,PUT",
     "REACH PICK WITHDRAW REACH-WITH-OBJ NO-OP REACH-WITH-OBJ PLACE-ON-BLOCK",
     [["fetch", ["reach01", "pick01", "withdraw01"]], ["fake", ["reach-with-obj01", "no-op01"]],
      ["put", ["reach-with-obj02", "place-on-block01"]]], []),
    ("Fig15-FAKE-outside-ACHIEVE-removed",
     "REACH NO-OP WITHDRAW REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE",
     [["fetch", ["reach02", "pick01"]], ["put", ["reach-with-obj01", "place-on-table01"]]],
     ["reach01", "no-op01", "withdraw01"]),
    ("Fig15-leading-WITHDRAW-removed", "WITHDRAW WITHDRAW REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE",
     [["fetch", ["reach01", "pick01"]], ["put", ["reach-with-obj01", "place-on-table01"]]],
     ["withdraw01", "withdraw02"]),
    ("Fig12-to-Fig17-trailing-WITHDRAWs-removed",
     "REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE WITHDRAW WITHDRAW",
     [["fetch", ["reach01", "pick01"]], ["put", ["reach-with-obj01", "place-on-table01"]]],
     ["withdraw01", "withdraw02"]),
    ("Fig15-PUT-keeps-a-WITHDRAW-inside-the-task",
     "REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE WITHDRAW REACH PICK REACH-WITH-OBJ PLACE-ON-BLOCK",
     [["fetch", ["reach01", "pick01"]],
      ["put", ["reach-with-obj01", "place-on-table01", "withdraw01"]]], []),
]


def _leaves(plan, name):
    plot = plan["operators"][name]["plot"]
    return [a[1] for a in plot[1:]] if plot[0] == "$sequence" else [plot[1]]


@pytest.mark.parametrize("words,parts,removed", [g[1:] for g in GOOD], ids=[g[0] for g in GOOD])
def test_templates_cover(words, parts, removed):
    result = run(words)
    plan = result.plan
    achieve = plan["operators"]["achieve01"]
    names = [a[1] for a in achieve["plot"][1:]]
    assert [[n.rstrip("0123456789"), _leaves(plan, n)] for n in names] == parts
    assert [op.name for op in result.removed] == removed


BAD = [  # (id, sequence, message fragment, where)
    ("PICK-without-REACH", "PICK REACH-WITH-OBJ PLACE-ON-TABLE",
     "no template covers PICK here", "operations[0]"),
    ("PLACE-without-FETCH",
     "REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE REACH-WITH-OBJ PLACE-ON-BLOCK",
     "no template covers PLACE-ON-BLOCK here", "operations[5]"),
    ("two-PICKs", "REACH PICK REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE",
     "no template covers PICK here", "operations[3]"),
    ("ends-holding", "REACH PICK REACH-WITH-OBJ",
     "the sequence ends inside a template", "operations[3]"),
    ("unknown-operation", "REACH PICK-FROM-BLOCK REACH-WITH-OBJ PLACE-ON-BLOCK",
     "operation PICK-FROM-BLOCK is not in the templates of templates.lark", "operations[1]"),
    ("fine-motion-at-top", "REACH PICK ALIGN REACH-WITH-OBJ PLACE-ON-TABLE",
     "operation ALIGN is not in the templates", "operations[2]"),
    ("only-redundant", "REACH NO-OP WITHDRAW", "all of it is redundant", "operations"),
]


@pytest.mark.parametrize("words,fragment,where", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_templates_reject(words, fragment, where):
    with pytest.raises(InputError) as info:
        run(words)
    assert fragment in info.value.message
    assert info.value.where == where
    assert info.value.file == "t.json"


def test_error_shows_the_operations_around_it():
    with pytest.raises(InputError) as info:
        run("REACH PICK REACH-WITH-OBJ PLACE-ON-TABLE "
            "REACH PICK PICK REACH-WITH-OBJ PLACE-ON-TABLE")
    assert "around it: ... reach02 pick02 [pick03] reach-with-obj02 place-on-table02" \
        in info.value.message
    assert "expected" in info.value.message and "REACH-WITH-OBJ" in info.value.message
