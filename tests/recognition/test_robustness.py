"""Robustness (issue #5): with noise.pixel doubled and noise.tremor tripled, every bundled
scenario is still recognized exactly (docs/seeing.md gives where recognition breaks)."""

from __future__ import annotations

import pytest

from lbw_engine.rules import load_rules
from perception.world.groundtruth import expected_operations

from .conftest import SCENARIOS, watch

RULES = load_rules()

PIXEL_FACTOR, TREMOR_FACTOR = 2.0, 3.0


@pytest.mark.parametrize("name", SCENARIOS)
def test_noisier_demonstration_gives_the_exact_sequence(name):
    from perception.world.scenario import load

    from .conftest import ROOT

    noise = load(ROOT / "scenarios" / f"{name}.yaml").noise
    w = watch(name, pixel=PIXEL_FACTOR * noise.pixel, tremor=TREMOR_FACTOR * noise.tremor)
    ops = [op["operation"] for op in w.actions["operations"]]
    assert ops == expected_operations(w.scenario, RULES)
    assert [set(op["target"]) for op in w.actions["operations"]] == [set(t.target)
                                                                      for t in w.truth]
