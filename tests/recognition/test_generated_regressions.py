"""Generated scenarios that used to be misrecognized at nominal noise (issue #7, `lbw bench`).

Each seed is one bench scenario (perception.world.generator, level nominal) whose
recognized top-level sequence once differed from the ground truth or whose
recorded supports were wrong. Now the sequence must equal the demonstrator's
and every moved object must end on the objects it really rests on.
"""

from __future__ import annotations

import pytest

from .generated import assert_sequence, assert_supports, assert_targets, watch_generated

CASES = {
    # a cube put on two pyramid cubes was recorded on one: :Join at a hesitation mid-descent
    "seed1009-pyramid-two-supports": 1009,
    # a cube on two cubes found over one at :Near (hand beside the spot): supports at the place
    "seed1057-pyramid-supports-at-release": 1057,
    # the loaded plank's pick reached for a rider cube; the cube then recorded on the pillar
    "seed1024-plank-between-riders": 1024,
    # a touch right after a place read as PLACE-ON-BLOCK (holder window without a held block)
    "seed1027-touch-after-place": 1027,
    # a tracker glitch as the hand left: an extra REACH + NO-OP before the WITHDRAW
    "seed1069-leaving-hand-no-near": 1069,
}


@pytest.mark.parametrize("seed", list(CASES.values()), ids=list(CASES))
@pytest.mark.heavy
def test_generated_scenario_recognized_exactly(seed):
    sc, rec, actions = watch_generated(seed, "nominal")
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


# A cube put across two cubes of a pyramid whose rows run along y: the hand came in over
# the first one, and the :Near search named it alone; set down, the cube shares 15 mm of
# its side with each (envnodes/placement.py beside_target adds the co-support)
TARGET_CASES = {"seed1144-pyramid-along-y-cap-on-two": (1144, "nominal", "classic"),
                # a 10 mm cube's pick waits for the palm to leave; the Transfer begun
                # meanwhile kept the target its :Near found (recognizer._rebind_successor)
                "seed1264-target-kept-after-a-deferred-pick": (1264, "nominal", "small")}


@pytest.mark.parametrize("case", list(TARGET_CASES.values()), ids=list(TARGET_CASES))
@pytest.mark.heavy
def test_generated_scenario_acts_on_the_demonstrated_objects(case):
    sc, rec, actions = watch_generated(*case)
    assert_sequence(sc, actions)
    assert_targets(sc, actions)
