"""A repair never turns a correct sequence into a wrong one (Sec. IX-C2, docs/repair.md):
what a perfect eye recognizes (the oracle, perception/world/oracle.py, under the
bundled rules) runs through rules/domain.yaml without a finding, so nothing is
changed. Rows: the bundled scenarios, generated ones covering every structure
of the generator (table; pyramid, inverted arch, tower; arch, pyramid; with
touches), the recorded Fig. 12 and Fig. 20 sequences, and a touch while carrying
(Fig. 15's FAKE with REACH-WITH-OBJ), which the generator never makes.
bench/bench_repair.py runs the same check over 100 generated seeds."""

import json
from pathlib import Path

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.understand.repair import repair_actions
from perception.world.generator import generate
from perception.world.oracle import oracle_recognizer
from perception.world.scenario import load, load_text

RULES = load_rules()
ROOT = Path(__file__).resolve().parents[2]
BUNDLED = sorted(p.stem for p in (ROOT / "scenarios").glob("*.yaml"))
GENERATED = (1000, 1001, 1002)

CARRY_TOUCH = """
name: carry-touch
shapes: {block: [40, 30, 50]}
teach:
  objects:
    block1: {shape: block, at: [-180, 100]}
    block2: {shape: block, at: [180, 300]}
  demonstration:
    - pick: block1
    - touch: block2
    - place: block1
      on: table
      at: [-20, 160]
"""


def scenario(case: str):
    if case in BUNDLED:
        return load(ROOT / "scenarios" / f"{case}.yaml")
    if case == "carry-touch":
        return load_text(CARRY_TOUCH)
    return generate(int(case)).scenario()


@pytest.mark.parametrize("case", [*BUNDLED, *map(str, GENERATED), "carry-touch"])
def test_what_a_perfect_eye_sees_is_left_as_it_is(case):
    actions = to_actions(oracle_recognizer(scenario(case), RULES))
    result = repair_actions(actions, RULES)
    assert result.checked and result.left == [] and result.repairs == []
    assert result.actions is actions


@pytest.mark.parametrize("name", ["fig12-inverted-arch", "fig20-build-table"])
def test_the_recorded_figures_are_left_as_they_are(name):
    actions = json.loads((ROOT / "tests" / "data" / f"{name}.actions.json").read_text())
    result = repair_actions(actions, RULES)
    assert result.checked and result.left == [] and result.repairs == []
