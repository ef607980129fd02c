"""Recognition repair (Sec. IX-C2, docs/repair.md): a table of recognized sequences,
hand-made from Fig. 12 (tests/data/fig12-inverted-arch.actions.json) with slips
injected, and what repair makes of each: the one change made, or none when no
single change or several fit. Each row: (case, slip, the repairs as (at, was,
now), the repaired sequence is Fig. 12's, inconsistencies left)."""

import copy
import json
from pathlib import Path

import pytest

from lbw_engine.report.metrics import plan_final_relations
from lbw_engine.rules import load_rules
from lbw_engine.understand import RelationTable, analyze, parse_actions
from lbw_engine.understand.consistency import run_sequence, start_state
from lbw_engine.understand.repair import repair_actions

RULES = load_rules()
DATA = Path(__file__).resolve().parents[1] / "data"
FIG12 = json.loads((DATA / "fig12-inverted-arch.actions.json").read_text())
NAMES = [op["name"] for op in FIG12["operations"]]


def at(ops, name):
    return next(i for i, op in enumerate(ops) if op["name"] == name)


def motion(name, operation, target, special, state):
    """A recognized operation whose snapshots are both ``state`` (it changed nothing)."""
    return {"name": name, "operation": operation, "base": ["hand"], "target": target,
            "special": special, "initial_state": copy.deepcopy(state),
            "final_state": copy.deepcopy(state)}


def touch_over_table(ops):
    """Fig. 12's first carry lowered over the table and lifted again before its place."""
    k = at(ops, "reach-with-obj01")
    state = ops[k]["final_state"]
    return [*ops[:k + 1], motion("no09", "NO-OP", ["table"], ["short-brick1"], state),
            *ops[k + 1:]]


def carry_cut_in_two(ops, name="reach-with-obj02", cut="no09"):
    """A local motion seen inside a carry (bench seeds 1014, 1026, 1095 at 4x noise)."""
    k = at(ops, name)
    carried = ops[k]["special"]
    # The first part went to the table: its snapshots hold the relations of its own nodes
    # (the hand and what it carries), not those of the blocks the carry came to.
    own = {"hand", *carried}
    mine = {"relations": [r for r in ops[k]["initial_state"]["relations"]
                          if own & {r[1], *(r[2] if isinstance(r[2], list) else [r[2]])}],
            "positions": ops[k]["initial_state"].get("positions", {})}
    first = dict(copy.deepcopy(ops[k]), name=f"{name}a", target=["table"],
                 initial_state=copy.deepcopy(mine), final_state=copy.deepcopy(mine))
    return [*ops[:k], first, motion(cut, "NO-OP", ["table"], carried, mine), *ops[k:]]


def pick_seen_as_touch(ops):
    """pick02 read as a NO-OP: nothing seemed to change."""
    k = at(ops, "pick02")
    return [*ops[:k], motion("no09", "NO-OP", ops[k]["target"], [], ops[k]["initial_state"]),
            *ops[k + 1:]]


def with_brick4(ops, k):
    """The relations before operation k, and where medium-brick4 rests (a snapshot shows
    what the hand goes to)."""
    seen = ops[at(ops, "reach03")]["initial_state"]["relations"]
    return {"relations": ops[k]["initial_state"]["relations"] + seen}


def touch_while_carrying(ops):
    """Fig. 15's FAKE with REACH-WITH-OBJ: medium-brick3 carried to medium-brick4, which
    is touched, then on to its place. Not a slip."""
    k = at(ops, "reach-with-obj02")
    state = with_brick4(ops, k)
    return [*ops[:k], motion("reach-with-obj09", "REACH-WITH-OBJ", ["medium-brick4"],
                             ["medium-brick3"], state),
            motion("no09", "NO-OP", ["medium-brick4"], ["medium-brick3"], state), *ops[k:]]


def touch_two_while_carrying(ops):
    """As ``touch_while_carrying``, the touch naming medium-brick4 and the block beside it
    (helper round 20, r07: a carried beam brought down onto one pillar reached the next
    one's edge). Deleting the touch, or reading it as a touch of either block alone, fit
    alike: none is made, and the touch is reported."""
    k = at(ops, "reach-with-obj02")
    state = with_brick4(ops, k)
    both = ["medium-brick4", "short-brick1"]
    return [*ops[:k], motion("reach-with-obj09", "REACH-WITH-OBJ", both, ["medium-brick3"],
                             state),
            motion("no09", "NO-OP", both, ["medium-brick3"], state), *ops[k:]]


def reach_elsewhere_first(ops):
    """A REACH to medium-brick4 just before reach02: dropping it or reading it as the hand
    leaving both fit."""
    k = at(ops, "reach02")
    return [*ops[:k], motion("reach09", "REACH", ["medium-brick4"], [], with_brick4(ops, k)),
            *ops[k:]]


def fetch_unseen(ops):
    """pick02 and reach-with-obj02 both missing: place-on-block01 holds nothing."""
    return [op for op in ops if op["name"] not in ("pick02", "reach-with-obj02")]


def two_carries_cut(ops):
    return carry_cut_in_two(carry_cut_in_two(ops), "reach-with-obj04", "no10")


def unfixable_then_cut(ops):
    return carry_cut_in_two(fetch_unseen(ops), "reach-with-obj04", "no10")


ROWS = [
    ("as-recognized", lambda ops: ops, [], True, 0),
    ("no-op-between-carry-and-its-place", touch_over_table,
     [(3, ["no09"], [])], True, 0),
    ("carry-cut-in-two", carry_cut_in_two,
     [(6, ["reach-with-obj02a", "no09", "reach-with-obj02"],
       [("reach-with-obj02a", "REACH-WITH-OBJ")])], True, 0),
    ("pick-seen-as-no-op", pick_seen_as_touch,
     [(5, ["no09"], [("pick02", "PICK")])], True, 0),
    ("touch-while-carrying-is-no-slip", touch_while_carrying, [], False, 0),
    ("two-changes-fit", reach_elsewhere_first, [], False, 1),
    ("touch-naming-two-blocks", touch_two_while_carrying, [], False, 2),
    ("no-change-fits", fetch_unseen, [], False, 1),
    ("two-slips-two-repairs", two_carries_cut,
     [(6, ["reach-with-obj02a", "no09", "reach-with-obj02"],
       [("reach-with-obj02a", "REACH-WITH-OBJ")]),
      (16, ["reach-with-obj04a", "no10", "reach-with-obj04"],
       [("reach-with-obj04a", "REACH-WITH-OBJ")])], True, 0),
    ("a-slip-after-one-left-as-is", unfixable_then_cut,
     [(14, ["reach-with-obj04a", "no10", "reach-with-obj04"],
       [("reach-with-obj04a", "REACH-WITH-OBJ")])], False, 1),
]


def repaired(slip):
    doc = {**copy.deepcopy(FIG12), "operations": slip(copy.deepcopy(FIG12["operations"]))}
    return doc, repair_actions(doc, RULES)


@pytest.mark.parametrize("case,slip,repairs,as_fig12,left", ROWS, ids=[r[0] for r in ROWS])
def test_repair(case, slip, repairs, as_fig12, left):
    doc, result = repaired(slip)
    got = [(r["at"], [w["name"] for w in r["was"]], [(n["name"], n["operation"])
                                                    for n in r["now"]])
           for r in result.repairs]
    assert got == repairs
    ops = result.actions["operations"]
    assert ([op["operation"] for op in ops] == [op["operation"] for op in FIG12["operations"]]) \
        == as_fig12
    assert len(result.left) == left, result.left
    if not repairs:  # nothing repaired: the document is the one recognized, untouched
        assert result.actions is doc and "repairs" not in doc
    for r in result.repairs:  # `at` is where `now` starts in the repaired sequence
        assert ops[r["at"]:r["at"] + len(r["now"])] == r["now"]
        assert any(f"{w['name']} " in r["why"] for w in r["was"]), r["why"]


def test_a_pick_read_anew_holds_its_object_and_the_plan_is_fig12s():
    _, result = repaired(pick_seen_as_touch)
    (fix,) = result.repairs
    assert ["holding", "hand", "medium-brick3"] in fix["now"][0]["final_state"]["relations"]

    def final(doc):
        seq = parse_actions(doc, RelationTable(RULES.analysis.tolerance))
        return plan_final_relations(analyze(seq, RULES.analysis).plan, RULES.roles.support)

    assert final(result.actions) == final(FIG12)


def test_a_rejoined_carry_keeps_the_first_start_and_the_last_end():
    ops = carry_cut_in_two(copy.deepcopy(FIG12["operations"]))
    for i, op in enumerate(ops):
        op["t_start"], op["t_end"] = float(i), i + 0.5
    _, result = repaired(lambda _: ops)
    (fix,) = result.repairs
    (joined,) = fix["now"]
    assert (joined["t_start"], joined["t_end"]) == (6.0, 8.5)
    assert joined["target"] == ["planar-brick2"]  # where the carry came to
    # ... and it changes no relation: its start's relations are those of the nodes it ends
    # with (bench seed 1026 at 4x: the legs' "on table" seen as added by the carry made the
    # leg the focus of the table top's place, and execution picked the leg up again)
    relations = [joined[s]["relations"] for s in ("initial_state", "final_state")]
    assert sorted(map(str, relations[0])) == sorted(map(str, relations[1]))


def test_what_is_wrong_is_said_in_the_findings():
    doc = {**FIG12, "operations": carry_cut_in_two(copy.deepcopy(FIG12["operations"]))}
    run = run_sequence(start_state(doc["operations"], doc["objects"], RULES), doc["operations"])
    assert [str(f) for f in run.findings] == \
        ["no09 (NO-OP): $object is table, a surface, not a block"]


def test_an_operation_without_a_domain_entry_is_not_checked():
    ops = copy.deepcopy(FIG12["operations"])
    ops[at(ops, "withdraw01")]["operation"] = "APPROACH"  # of operations.yaml, not domain.yaml
    result = repair_actions({**FIG12, "operations": ops}, RULES)
    assert not result.checked and result.repairs == []
    assert any("APPROACH has no entry in domain.yaml" in s for s in result.left)
