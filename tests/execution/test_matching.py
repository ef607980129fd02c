"""Initial-state matching (Sec. VII-A steps 1-5): one case per situation the section names."""

import pytest

from lbw_engine.do.matching import Measured, match_initial_state
from lbw_engine.errors import TaskFailed

BRICK, PLATE, CUBE = (30.0, 30.0, 50.0), (120.0, 100.0, 10.0), (40.0, 40.0, 40.0)


def m(shape, x, y):
    """A measured object resting on the table."""
    size = {"brick": BRICK, "plate": PLATE, "cube": CUBE}[shape]
    return Measured(shape, (float(x), float(y), size[2] / 2), size)


TAUGHT = {
    "brick1": {"shape": "brick", "position": [-150, 200, 25]},
    "brick2": {"shape": "brick", "position": [-100, 320, 25]},
    "plate1": {"shape": "plate", "position": [150, 220, 5]},
    "cube9": {"shape": "cube", "position": [0, 50, 20]},  # taught but not used by the plan
}

# (taught, relevant, measured, expected name -> measured index, expected unmatched)
CASES = [
    pytest.param(TAUGHT, ["plate1", "brick1"], [m("brick", 10, 10), m("plate", 200, 300)],
                 {"plate1": 1, "brick1": 0}, [], id="SecVIIA-two-stage-by-shape"),
    pytest.param(TAUGHT, ["brick1", "plate1"],
                 [m("cube", 0, 0), m("plate", 200, 300), m("brick", 10, 10), m("cube", 90, 90)],
                 {"brick1": 2, "plate1": 1}, [0, 3], id="SecVIIA-irrelevant-objects-both-sides"),
    pytest.param(TAUGHT, ["brick2", "brick1"],
                 [m("brick", 50, 50), m("plate", 0, 0), m("brick", -50, 50), m("brick", 9, 9)],
                 {"brick2": 0, "brick1": 2}, [1, 3],
                 id="SecVIIA-equal-shapes-first-come-first-served"),
    pytest.param(TAUGHT, [], [m("brick", 1, 1)], {}, [0], id="SecVIIA-empty-plan"),
]


@pytest.mark.parametrize("taught,relevant,measured,want,unmatched", CASES)
def test_matching(taught, relevant, measured, want, unmatched):
    got = match_initial_state(taught, relevant, measured)
    assert got.assigned == want
    assert got.unmatched == unmatched
    assert got.positions == {n: measured[i].position for n, i in want.items()}


@pytest.mark.parametrize(
    "relevant,measured,needle",
    [
        pytest.param(["brick1", "plate1"], [m("brick", 1, 1), m("cube", 5, 5)], "plate1",
                     id="SecVIIA-missing-shape"),
        pytest.param(["brick1", "brick2"], [m("brick", 1, 1), m("plate", 5, 5)], "brick2",
                     id="SecVIIA-too-few-of-a-shape"),
        pytest.param(["ghost"], [m("brick", 1, 1)], "ghost", id="SecVIIA-unknown-plan-object"),
    ],
)
def test_missing_shape_is_a_task_failure_naming_the_object(relevant, measured, needle):
    with pytest.raises(TaskFailed) as exc:
        match_initial_state(TAUGHT, relevant, measured)
    assert f"'{needle}'" in str(exc.value)
    assert exc.value.exit_code == 1


def test_an_anchored_object_takes_the_measured_one_nearest_its_taught_spot():
    """First come, first served would give k1 the first cube measured; anchored (the plan
    never moves it and needs it at (-40, 200)), it takes the cube standing there."""
    from lbw_engine.do.matching import Measured, match_initial_state

    taught = {n: {"shape": "cube"} for n in ("k1", "k2", "k3")}
    measured = [Measured("cube", (100.0, 60.0, 15.0), (30, 30, 30)),
                Measured("cube", (220.0, 250.0, 15.0), (30, 30, 30)),
                Measured("cube", (-40.0, 201.0, 15.0), (30, 30, 30))]
    m = match_initial_state(taught, ["k1", "k2", "k3"], measured, {"k1": (-40.0, 200.0, 15.0)})
    assert m.assigned == {"k1": 2, "k2": 0, "k3": 1}
    assert match_initial_state(taught, ["k1", "k2", "k3"], measured).assigned["k1"] == 0


STACKS = [  # measured: a cube on a block, a cube on a cube (generated twins 3107's layout)
    Measured("cube", (120.0, 55.0, 70.0), CUBE), Measured("block", (120.0, 55.0, 25.0),
                                                         (50.0, 50.0, 50.0)),
    Measured("cube", (-246.0, 85.0, 60.0), CUBE), Measured("cube", (-247.0, 85.0, 20.0), CUBE)]


@pytest.mark.parametrize("relevant,stacked,want", [
    # the base taught carrying the rider goes to the cube carrying one, and the rider to
    # the cube on it; first come, first served (uncovered first) gave the base the cube
    # on the block and the rider the other stack's top
    (["base", "rider", "mid"], [("rider", "base")], {"base": 3, "rider": 2, "mid": 0}),
    # the stack taught apart: first come, first served, uncovered first, as before
    (["base", "rider", "mid"], [], {"base": 0, "rider": 2, "mid": 3}),
    # a pair the workspace does not have (a cube on a disc) changes nothing
    (["base", "rider", "mid"], [("rider", "disc1")], {"base": 0, "rider": 2, "mid": 3}),
], ids=["SecVIIA-a-taught-stack-keeps-its-pair", "SecVIIA-no-stack-taught",
        "SecVIIA-a-stack-not-measured"])
def test_objects_taught_one_on_another_take_a_measured_pair(relevant, stacked, want):
    taught = {n: {"shape": "cube"} for n in relevant}
    assert match_initial_state(taught, relevant, STACKS, stacked=stacked).assigned == want


@pytest.mark.parametrize("order", [[0, 1, 2], [2, 1, 0], [1, 2, 0]], ids=str)
def test_three_equal_blocks_taught_stacked_keep_their_order(order):
    """Review of stop 32: c1 on c2 on c3, three equal cubes, measured bottom first: the
    pairs taken in name order gave the taught top the middle cube and the taught bottom
    the top one. Pairs go bottom first, each lower block as many blocks up as taught."""
    tower = [Measured("cube", (0.0, 200.0, 15.0 + 30.0 * k), (30.0, 30.0, 30.0)) for k in range(3)]
    measured = [tower[k] for k in order]
    taught = {n: {"shape": "cube"} for n in ("c1", "c2", "c3")}
    got = match_initial_state(taught, ["c1", "c2", "c3"], measured,
                              stacked=[("c1", "c2"), ("c2", "c3")]).assigned
    assert {n: order[i] for n, i in got.items()} == {"c3": 0, "c2": 1, "c1": 2}
