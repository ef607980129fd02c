"""Static balance when the branches of a $parallel are ordered (Fig. 14, inverted arch).

Generated seed 1048 (nominal) puts the plank on its pillar before the two
cubes, which the learned plan lists as a $parallel; its first listed cube goes
on the plank's overhanging end and tipped the plank. The plan is the one the
recognizer learned, stored so the test does not depend on recognition.
"""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.do.balance import unbalanced
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parent / "data"


def _arch(cubes: dict[str, float]) -> EnvModel:
    """A plank on a 50 mm pillar, its centre 14 mm off the pillar's, cubes at plank x."""
    bodies = {"pillar": Body("block", (50, 50, 50), (0, 0, 25)),
              "plank": Body("plank", (160, 60, 20), (14, 0, 60))}
    for name, x in cubes.items():
        bodies[name] = Body("cube", (40, 40, 40), (14 + x, 0, 90))
    return EnvModel.measured(load_rules(), bodies, (0, 200, 200))


@pytest.mark.parametrize(("cubes", "tips"), [
    ({}, None),
    ({"cube-far": 51}, "plank"),            # the overhanging end alone tips the plank
    ({"cube-near": -52}, None),             # the end over the pillar alone holds
    ({"cube-far": 51, "cube-near": -52}, None),  # both: the taught arch stands
], ids=["Fig14-plank-alone", "Fig14-far-cube-first", "Fig14-near-cube-first",
        "Fig14-both-cubes"])
def test_unbalanced(cubes, tips):
    assert unbalanced(_arch(cubes), margin=2.0) == tips


def test_seed_1048_learned_plan_executes_and_verifies():
    rules = load_rules()
    plan = planmod.load(DATA / "gen-1048-nominal.plan.json")
    result = execute_plan(plan, load(DATA / "gen-1048-nominal.yaml"), rules)
    assert result.success, result.message
    # The cube next to the pillar went onto the plank first (the listed order
    # would have put the overhanging one first).
    puts = [op for op in result.trace.ops
            if op.focus in ("inv2-cube1", "inv2-cube2") and op.goal is not None
            and op.goal[2] > 80]
    pillar = result.trace.model.bodies["inv2-pillar"].position
    first, second = puts[0].goal, puts[-1].goal
    assert puts[0].focus != puts[-1].focus
    assert abs(first[0] - pillar[0]) < abs(second[0] - pillar[0])
