"""A loaded plank put on its pillar where the plan says, when that spot cannot hold it.

Generated seeds 1073 (2x noise) and 1086 (4x) learn the inverted arch's
PACHIEVE (Fig. 14: the plank, two cubes riding, lifted onto the pillar) with
the plank's offset on the pillar measured 40 mm and 34 mm off centre; in the
demonstration it lay centred (ground truth: 0.1 mm and 0.2 mm). The robot
carried the loaded plank cleanly, but put it there: the load's centre of mass
was beyond the pillar's edge, the plank tipped when the jaws opened and shed
the cubes. The plans are the ones the recognizer learned, stored so these
tests do not depend on recognition.
"""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.do.balance import steadied, unbalanced
from lbw_engine.do.listing import format_commands
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parent / "data"
RULESET = load_rules()
RULES = RULESET.commands


def _held_plank(riders: dict[str, float]) -> EnvModel:
    """A pillar at x = 0, and a plank held above it with cubes at these plank x."""
    bodies = {"pillar": Body("block", (50, 50, 50), (0, 0, 25)),
              "plank": Body("plank", (160, 60, 20), (300, 0, 190))}
    for name, x in riders.items():
        bodies[name] = Body("cube", (40, 40, 40), (300 + x, 0, 220))
    model = EnvModel.measured(RULESET, bodies, (300, 0, 200))
    model.hold("plank")
    return model


@pytest.mark.parametrize(("riders", "xy", "want"), [
    ({"c1": -48, "c2": 46}, (40, 0), 17 + 0.4),   # Fig. 14 load, 40 mm off: 8 mm inside
    ({"c1": -48, "c2": 46}, (-40, 3), -17 + 0.4),  # the other side, y kept
    ({"c1": -48, "c2": 46}, (10, 0), 10),         # stands where taught: not moved
    ({"c1": 50}, (-45, 0), -17 - 50 * 64 / 256),  # one cube: its weight counts
    ({}, (22, 0), 22),                            # 3 mm inside the edge: stands
], ids=["loaded-40mm-right", "loaded-40mm-left", "loaded-balanced", "one-rider-off",
        "empty-near-edge"])
def test_steadied_moves_only_a_load_that_would_tip(riders, xy, want):
    model = _held_plank(riders)
    (x, y), moved = steadied(model, "plank", xy, ["pillar"], 2.0, 8.0)
    assert x == pytest.approx(want, abs=0.05)
    assert y == xy[1] and moved == pytest.approx(abs(x - xy[0]))


def test_placements_on_the_table_are_never_moved():
    model = _held_plank({"c1": -48})
    assert steadied(model, "plank", (500, 0), ["table"], 2.0, 8.0) == ((500, 0), 0.0)


@pytest.mark.parametrize("case", ["gen-1073-2x", "gen-1086-4x"])
def test_learned_loaded_plank_is_put_where_it_stands(case):
    plan = planmod.load(DATA / f"{case}.plan.json")
    result = execute_plan(plan, load(DATA / f"{case}.yaml"), RULESET)
    assert result.success, result.message
    plank = next(n for n in result.trace.model.bodies if n.endswith("-plank"))
    put = [op for op in result.trace.ops if op.focus == plank and op.steadied > 0]
    assert put, "the plank's taught spot on the pillar would have tipped it"
    assert unbalanced(result.trace.model, RULES.balance_margin) is None
    assert "mm from the taught spot" in format_commands(result.trace)
