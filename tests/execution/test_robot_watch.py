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
from lbw_engine.do.opcheck import (
    PLACE_MM,
    PUSHED,
    SET_ASIDE,
    Op,
    differences,
    moving_operations,
    unplaced,
)
from lbw_engine.paths import bundled_scenario
from lbw_engine.rules import load_rules

DATA = Path(__file__).resolve().parent.parent / "data"

# classes as effects.yaml gives them: into the hand (follow) or onto a support (place)
P, T = Op("PICK", "a", "follow"), Op("PLACE-ON-TABLE", "a", "place")
B = Op("PLACE-ON-BLOCK", "b", "place")

# executed, recognized, expected differences as (object, expected, observed), and the
# objects whose executed place was not seen as executed (redone once: a drop)
CASES = [
    pytest.param([P, T], [P, T], [], set(), id="same"),
    pytest.param([P, T], [P], [("a", "PLACE-ON-TABLE a", None)], {"a"}, id="missing-place"),
    pytest.param([P, T], [P, T, Op("PICK", "c", "follow")], [("c", None, "PICK c")],
                 set(), id="extra-op"),
    pytest.param([P, T], [P, Op("PLACE-ON-TABLE", "c", "place")],
                 [("a", "PLACE-ON-TABLE a", "PLACE-ON-TABLE c")], {"a"}, id="wrong-object"),
    pytest.param([P, T], [P, Op("PICK", "a", "follow")],
                 [("a", "PLACE-ON-TABLE a", "PICK a")], {"a"}, id="place-seen-as-pick"),
    # the support (table or block) is the state comparison's to judge
    pytest.param([P, B], [P, Op("PLACE-ON-TABLE", "b", "place")], [], set(), id="other-support"),
    pytest.param([P, T], [], [("a", "PICK a", None), ("a", "PLACE-ON-TABLE a", None)],
                 {"a"}, id="nothing-seen"),
    # a place is judged where the recognizer saw the object appear (x, y), within PLACE_MM
    pytest.param([P, Op("PLACE-ON-TABLE", "a", "place", (0.0, 100.0))],
                 [P, Op("PLACE-ON-TABLE", "a", "place", (PLACE_MM - 5.0, 100.0))], [],
                 set(), id="placed-near-goal"),
    pytest.param([P, Op("PLACE-ON-TABLE", "a", "place", (0.0, 100.0))],
                 [P, Op("PLACE-ON-TABLE", "a", "place", (PLACE_MM + 5.0, 100.0))],
                 [("a", "PLACE-ON-TABLE a at (0, 100)",
                   f"PLACE-ON-TABLE a at ({PLACE_MM + 5:.0f}, 100)")],
                 {"a"}, id="placed-elsewhere"),
    # a block set aside (no plan object) is expected if seen, not required, never redone
    # (lbw bench 1107 at 4x: the watch missed a tile's set-aside, and the redo looked up
    # the tile's shape and crashed)
    pytest.param([Op(SET_ASIDE, "u", "follow"), Op(SET_ASIDE, "u", "place", (0.0, 50.0)),
                  P, T],
                 [Op("PICK", "u", "follow"), P, T], [], set(), id="set-aside-half-seen"),
    pytest.param([Op(SET_ASIDE, "u", "follow"), Op(SET_ASIDE, "u", "place", (0.0, 50.0)),
                  P, T], [P, T], [], set(), id="set-aside-unseen"),
    pytest.param([Op(SET_ASIDE, "u", "follow"), Op(SET_ASIDE, "u", "place", (0.0, 50.0)),
                  P, T],
                 [Op("PICK", "u", "follow"), Op("PLACE-ON-TABLE", "u", "place", (2.0, 50.0)),
                  P, T], [], set(), id="set-aside-seen"),
    # the watch names a block the plan does not have its own way (bench 1251, 4x)
    pytest.param([Op(SET_ASIDE, "unused-cube-2", "follow"),
                  Op(SET_ASIDE, "unused-cube-2", "place", (0.0, 50.0)), P, T],
                 [Op("PICK", "unused:1", "follow"),
                  Op("PLACE-ON-TABLE", "unused:1", "place", (1.0, 50.0)), P, T], [], set(),
                 id="set-aside-seen-under-another-name"),
    # a block the closed jaws push into contact after its place may be seen taken again
    # (helper round 10, x27), or not at all; either is no difference
    pytest.param([P, T, Op(PUSHED, "a", "follow"), Op(PUSHED, "a", "place")],
                 [P, T, Op("PICK", "a", "follow")], [], set(), id="push-seen-as-a-pick"),
    pytest.param([P, T, Op(PUSHED, "a", "follow"), Op(PUSHED, "a", "place")], [P, T], [],
                 set(), id="push-unseen"),
    pytest.param([P, T, Op(PUSHED, "a", "follow"), Op(PUSHED, "a", "place")],
                 [P, T, Op("PICK", "c", "follow")], [("a", "pushed a", "PICK c")], set(),
                 id="push-of-another-block-is-one"),
    # a block moved with another riding on it may be seen as the rider's move (helper
    # round 16, 51): no difference, unless the rider is seen put down elsewhere
    pytest.param([Op("PICK", "a", "follow", None, frozenset({"c"})),
                  Op("PLACE-ON-TABLE", "a", "place", (0.0, 100.0), frozenset({"c"}))],
                 [Op("PICK", "c", "follow"), Op("PLACE-ON-TABLE", "c", "place", (1.0, 99.0))],
                 [], set(), id="moved-with-a-rider-seen-as-the-rider"),
    pytest.param([Op("PICK", "a", "follow", None, frozenset({"c"})),
                  Op("PLACE-ON-TABLE", "a", "place", (0.0, 100.0), frozenset({"c"}))],
                 [Op("PICK", "c", "follow"),
                  Op("PLACE-ON-TABLE", "c", "place", (PLACE_MM + 5.0, 100.0))],
                 [("a", "PLACE-ON-TABLE a at (0, 100)",
                   f"PLACE-ON-TABLE c at ({PLACE_MM + 5:.0f}, 100)")], {"a"},
                 id="rider-seen-put-down-elsewhere"),
]


@pytest.mark.parametrize("executed,recognized,expected,missed", CASES)
def test_differences(executed, recognized, expected, missed):
    diffs = differences(executed, recognized)
    assert [(d["object"], d["expected"], d["observed"]) for d in diffs] == expected
    assert unplaced(diffs) == missed


def test_the_compared_operations_are_those_whose_effect_moves_an_object():
    rules = load_rules()
    moving = moving_operations(rules.effects)
    assert set(moving) == {op for op, r in rules.effects.items() if r.move}
    for op, (kind, var, feature) in moving.items():
        move = rules.effects[op].move
        assert kind in move and f"${var}" in move.values() and feature == move.get("measured")
    assert {kind for kind, _, _ in moving.values()} == {"follow", "place"}


def execute(tmp_path, scenario, capsys, plan="unstack.plan.json"):
    out = tmp_path / "out"
    code = main(["execute", str(DATA / plan), str(scenario), "--out", str(out)])
    err = capsys.readouterr().err
    return code, json.loads((out / "execution.json").read_text()), err


def test_fault_free_robot_operations_are_recognized_as_executed(tmp_path, capsys):
    code, report, err = execute(tmp_path, bundled_scenario("unstack"), capsys)
    assert code == 0, err
    ops = report["monitor"]["operations"]
    assert [o["operator"] for o in ops] == ["achieve01"]
    moved = ops[0]["moving"]
    names = [t.split(" at ")[0] for t in moved["executed"]]
    assert names == ["PICK top1", "PLACE-ON-TABLE top1"]
    assert [t.split(" at ")[0] for t in moved["recognized"]] == names
    assert ops[0]["agree"] is True
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
    assert first["operator"] == "achieve01"
    # The block fell 30 mm short of its goal, inside the place's window: the robot's
    # place is seen there (from above, ChangeNode.unknown_top), not at the goal, or not
    # at all; either way the block is not where the ACHIEVE puts it.
    placed = [m for m in first["moving"]["recognized"] if m.startswith("PLACE-ON-TABLE top1")]
    assert not placed or placed[0] != first["moving"]["executed"][-1]
    seen = [d for d in report["monitor"]["detections"] if d["object"] == "top1"]
    assert seen and seen[0]["operator"] == "achieve01"
    assert {d["kind"] for d in seen} & {"operation", "position"}
    assert seen[0]["t"] >= report["faults"][0]["t"]


def test_a_block_set_down_behind_another_is_seen_placed(tmp_path, capsys):
    """Fault bench seed 9007 (2x), run without faults: the robot sets a pyramid's middle
    cube down behind the front one, as the side camera sees it, and lifts straight up,
    so neither view shows the change at the gripper's :Far. The holder window between
    the open jaws then looked at another cube far behind (0.42 block pixels, "still
    holding"): the place was read as a NO-OP, a false detection, and the unit was done
    twice. Pixels a known object explains no longer count as held (ChangeNode.unexplained).
    """
    code, report, err = execute(tmp_path, DATA / "behind.yaml", capsys, "behind.plan.json")
    assert code == 0, err
    assert report["monitor"]["detections"] == []
    assert all(o["agree"] for o in report["monitor"]["operations"])
    assert len(report["monitor"]["operations"]) == 11  # each unit once


def test_a_pick_behind_a_taller_tower_is_judged_once_its_spot_shows(tmp_path, capsys):
    """Helper round 15's AI: a staircase whose last cube starts behind the 3-high tower
    already built, as the side camera sees it, with the jaws closing along y (the near
    jaw hides the held cube from the side) and the palm over its spot from above. No view
    told whether it was taken, the holder window showed nothing: the pick and its place
    were watched as NO-OPs and the unit redone (a fault-free run with two detections). The
    pick is now judged once a view shows its spot (ChangeNode.too_small)."""
    code, report, err = execute(tmp_path, DATA / "staircase-picked-behind-its-tower.yaml",
                                capsys, "staircase-picked-behind-its-tower.plan.json")
    assert code == 0, err
    assert report["monitor"]["detections"] == []
    assert report["monitor"]["repairs"] == []
    assert all(o["agree"] for o in report["monitor"]["operations"])


def test_a_block_lifted_with_its_rider_is_watched_as_executed():
    """Helper round 16, 51: the middle cube of a three-cube tower is taken with the top
    one riding on it. The watch names the move by the top face it sees move, the
    rider's: two detections and the unit redone in a fault-free run. A move seen as the
    move of a block riding on the one moved is none (opcheck.differences)."""
    from lbw_engine.pipeline.run import run
    from perception.world.scenario import load

    result = run(load(DATA / "middle-cube-lifted-with-its-rider.yaml"))
    assert result.failure is None, result.failure
    report = result.execution.report
    assert report["monitor"]["detections"] == []
    assert report["verification"] == {"cameras": True, "ground_truth": True}
