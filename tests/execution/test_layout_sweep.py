"""A plan executes in random execution layouts (issue #6's seeded sweep, a slice of it).

The full sweep with plans learned by watching is `python -m bench layouts`;
here the hand-written plans of tests/data keep the test independent of the
recognizer.
"""

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from bench.bench_layouts import random_layout, with_layout  # noqa: E402
from lbw_engine.do import plan as planmod  # noqa: E402
from lbw_engine.paths import bundled_scenario  # noqa: E402
from lbw_engine.pipeline.execute import execute_plan  # noqa: E402
from lbw_engine.rules import load_rules  # noqa: E402
from perception.world.scenario import load  # noqa: E402

CASES = [(name, seed) for name in ("build-table", "inverted-arch") for seed in (11, 12, 13)]


@pytest.mark.parametrize("name,seed", CASES, ids=[f"{n}-layout{s}" for n, s in CASES])
def test_plan_verifies_in_a_random_layout(name, seed):
    scenario = load(bundled_scenario(name))
    layout = random_layout(scenario, seed)
    shapes = {o.shape for o in scenario.execute.objects.values()}
    assert {v["shape"] for v in layout.values()} == shapes
    sc = with_layout(bundled_scenario(name), layout, seed)
    plan = planmod.load(ROOT / "tests" / "data" / f"{name}.plan.json")
    result = execute_plan(plan, sc, load_rules())
    assert result.success, result.message
    assert result.report["mismatches"] == []


def test_layouts_differ_by_seed_and_repeat_per_seed():
    scenario = load(bundled_scenario("build-table"))
    assert random_layout(scenario, 1) == random_layout(scenario, 1)
    assert random_layout(scenario, 1) != random_layout(scenario, 2)
