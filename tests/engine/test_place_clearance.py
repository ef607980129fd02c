"""A placed block's measured centre is moved out of a neighbour it overlaps by a
measurement error (rules/constants.yaml place-clearance / place-overlap-limit),
as Sec. V-B4 corrects the vertical position from the support's size."""

import pytest

from lbw_engine.model.effects import _clear_of_neighbours
from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.rules import load_rules

SIZE = (40.0, 30.0, 50.0)
NEIGHBOUR = (-20.0, 160.0, 25.0)

# (case id, measured centre of the placed block, expected centre after correction)
CASES = [
    ("overlap-0.8mm-north", (-18.0, 189.2, 25.0), (-18.0, 191.0, 25.0)),
    ("overlap-3mm-east", (17.0, 165.0, 25.0), (21.0, 165.0, 25.0)),
    ("apart-unchanged", (-20.0, 195.0, 25.0), (-20.0, 195.0, 25.0)),
    ("deep-overlap-left-alone", (-20.0, 170.0, 25.0), (-20.0, 170.0, 25.0)),
    ("other-height-unchanged", (-20.0, 185.0, 75.0), (-20.0, 185.0, 75.0)),
]


@pytest.fixture(scope="module")
def rules():
    return load_rules(None)


@pytest.mark.parametrize("measured,expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_clear_of_neighbours(rules, measured, expected):
    env = EnvModel(rules)
    env.nodes["block1"] = EnvNode("block1", "Loc", NEIGHBOUR, SIZE, "block")
    placed = EnvNode("block2", "Loc", None, SIZE, "block")
    env.nodes["block2"] = placed
    got = _clear_of_neighbours(env, placed, measured, set())
    assert got == pytest.approx(expected)


def test_supports_are_not_pushed_against(rules):
    env = EnvModel(rules)
    env.nodes["base"] = EnvNode("base", "Loc", (0.0, 200.0, 25.0), SIZE, "block")
    placed = EnvNode("top", "Loc", None, SIZE, "block")
    env.nodes["top"] = placed
    assert _clear_of_neighbours(env, placed, (0.0, 200.0, 30.0), {"base"}) == (0.0, 200.0, 30.0)
