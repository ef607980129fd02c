"""The operations of rules/domain.yaml on a symbolic state (Sec. IX-C2): a table of
sequences, the first step whose preconditions fail (None: all hold), and facts
that hold at the end. Rows are hand-made from Fig. 12 (the inverted arch) and
from the two recognition slips issue #13 names."""

import pytest

from lbw_engine.rules.domain import load_domain
from lbw_engine.understand.domain import apply, check, find_bindings, run

D = load_domain()
H = {"hand": "hand"}
INIT = frozenset({
    ("hand-empty", "hand"), ("hand-away", "hand"), ("clear", "b"), ("clear", "p"),
    ("on", "b", "table", "b-now"), ("on", "p", "table", "p-now"),
    ("site", "b-now", "table"), ("site", "p-now", "table"), ("site", "b-goal", "p"),
    ("place-of", "b-goal", "b"), ("place-of", "b-now", "b"), ("place-of", "p-now", "p"),
})
REACH_B = ("REACH", {**H, "object": "b"})
PICK_B = ("PICK", {**H, "object": "b", "from": ("table",), "at": "b-now"})
CARRY_B = ("REACH-WITH-OBJ", {**H, "object": "b", "place": "b-goal"})
PLACE_B = ("PLACE-ON-BLOCK", {**H, "object": "b", "support": ("p",), "table": "table",
                              "place": "b-goal"})
TOUCH_B = ("NO-OP", {**H, "object": "b"})
TOUCH_P = ("NO-OP", {**H, "object": "p"})

ROWS = [
    ("fetch-put", [REACH_B, PICK_B, CARRY_B, PLACE_B], None,
     {("on", "b", "p", "b-goal"), ("hand-empty", "hand")}),
    ("touch-then-fetch", [REACH_B, TOUCH_B, REACH_B, PICK_B], None, {("holding", "hand", "b")}),
    # A touch ends the approach: a PLACE right after it has no place to go to.
    ("no-op-while-carrying", [REACH_B, PICK_B, CARRY_B, TOUCH_B, PLACE_B], 4, set()),
    # Fig. 15's FAKE while carrying: touch p with b in the hand, carry b on, put it down.
    ("touch-while-carrying", [REACH_B, PICK_B, CARRY_B, TOUCH_P, CARRY_B, PLACE_B], None,
     {("on", "b", "p", "b-goal")}),
    ("pick-seen-as-no-op", [REACH_B, TOUCH_B, CARRY_B, PLACE_B], 2, set()),
    ("pick-without-reach", [PICK_B], 0, set()),
    ("withdraw-anytime", [("WITHDRAW", H), REACH_B, ("WITHDRAW", H)], None, set()),
    ("align-while-holding", [REACH_B, PICK_B, ("ALIGN", {**H, "object": "b", "other": "p"})],
     None, {("coplanar", "b", "p")}),
]


@pytest.mark.parametrize("case,steps,first_bad,holds", ROWS, ids=[r[0] for r in ROWS])
def test_sequence(case, steps, first_bad, holds):
    final, problems = run(INIT, [(D.operations[o], b) for o, b in steps])
    assert (problems[0][0] if problems else None) == first_bad
    assert holds <= final


def test_pick_lifts_from_several_supports_and_finds_them():
    on_two = frozenset({("hand-empty", "hand"), ("hand-at", "hand", "t"), ("clear", "t"),
                        ("on-multiple", "t", "l", "t-goal"), ("on-multiple", "t", "r", "t-goal"),
                        ("co-support", "l", "t", "t-goal"), ("co-support", "r", "t", "t-goal"),
                        ("site", "t-goal", "l"), ("site", "t-goal", "r")})
    pick = D.operations["PICK"]
    found = find_bindings(on_two, pick, {**H, "object": "t"})
    assert found["from"] == ("l", "r") and found["at"] == "t-goal"
    assert check(on_two, pick, found) == []
    after = apply(on_two, pick, found)
    assert not any(f[0] in ("on-multiple", "co-support") for f in after)
    assert ("holding", "hand", "t") in after


def test_planner_preconditions_are_separate():
    loaded = INIT - {("clear", "p")}
    pick_p = D.operations["PICK"]
    b = {**H, "object": "p", "from": ("table",), "at": "p-now"}
    state = apply(loaded, D.operations["REACH"], {**H, "object": "p"})
    assert check(state, pick_p, b) == []  # a person may lift a loaded plank (Fig. 14)
    assert check(state, pick_p, b, planner=True) == [("clear", "p")]


def test_a_planner_touches_only_with_the_empty_hand():
    steps = [(D.operations[o], b) for o, b in [REACH_B, PICK_B, CARRY_B, TOUCH_P]]
    assert run(INIT, steps)[1] == []
    assert run(INIT, steps, planner=True)[1] == [
        (3, [("hand-empty", "hand"), ("hand-at", "hand", "p")])]
