"""A load taught across supports the demonstration never moved (placement._check_reach).

Helper round 17, u63: a slab taught across a pillar and a two-cube stack that stood
100 mm apart, neither of them moved. In an execution layout where they stand farther
apart than the slab spans, no place rests it on both: the task is refused at
instantiation, naming them, before the robot moves (four repairs had put it on the
table). Where they stand as taught, elsewhere on the table, it is done.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load_text

DATA = Path(__file__).resolve().parent.parent / "data"
NAME = "lintel-on-unmoved-supports"


@pytest.mark.parametrize(("pillar", "stack", "done"), [
    ((200, 100), (-200, 300), False),   # 447 mm apart: refused
    ((-100, 200), (0, 200), True),      # 100 mm apart along x, as taught
    ((150, 60), (250, 60), True),       # ... elsewhere on the table
], ids=["447mm-apart", "as-taught", "as-taught-elsewhere"])
def test_a_load_across_unmoved_supports_is_done_only_where_it_reaches_them(pillar, stack, done):
    text = (DATA / f"{NAME}.yaml").read_text()
    text = text.replace("q1: {shape: pillar, at: [200, 100]}",
                        f"q1: {{shape: pillar, at: [{pillar[0]}, {pillar[1]}]}}")
    text = text.replace("d1: {shape: cube, at: [-200, 300]}",
                        f"d1: {{shape: cube, at: [{stack[0]}, {stack[1]}]}}")
    result = execute_plan(planmod.load(DATA / f"{NAME}.plan.json"), load_text(text, NAME),
                          load_rules())
    report = result.report
    if done:
        assert result.success, result.message
        assert report["verification"] == {"cameras": True, "ground_truth": True}
    else:
        assert not result.success and report["stage"] == "instantiation"
        assert "on c2, p1: they stand up to 447 mm apart" in result.message, result.message
