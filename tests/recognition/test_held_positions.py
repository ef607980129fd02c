"""Positions of a carried block in actions.json (design.md: a PICK's final state has the
block lifted with the hand).

Before stop 38 the environment model left a picked block at its table spot; the hand's
later moves then shifted it by their own displacement, so a block carried down towards
its place was recorded up to 82 mm under the table top (helper round 20, C7).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .generated import watch_file

DATA = Path(__file__).parent / "data"
SCENARIOS = Path(__file__).parents[2] / "scenarios"


@pytest.mark.parametrize("path", [SCENARIOS / "tower.yaml",
                                  DATA / "small-cubes-close-row-along-x.yaml"],
                         ids=["tower", "small-cubes-close-row"])
def test_a_carried_block_hangs_under_the_hand(path):
    sc, _, actions = watch_file(path)
    carried = 0
    for op in actions["operations"]:
        held = [r[1] for r in op["final_state"]["relations"] if r[0] == "held-by"]
        if not held:
            continue
        name, pos = held[0], op["final_state"]["positions"]
        size = sc.shapes[actions["objects"][name]["shape"]]
        hand = pos["hand"]
        assert pos[name][2] - size[2] / 2 > 5.0, (op["name"], pos[name])  # off the table
        # under the hand, x and y within the block's footprint, the hand not below it
        assert abs(pos[name][0] - hand[0]) <= size[0] / 2 + 5.0, (op["name"], pos)
        assert abs(pos[name][1] - hand[1]) <= size[1] / 2 + 5.0, (op["name"], pos)
        assert hand[2] >= pos[name][2] - size[2] / 2, (op["name"], pos)
        if op["operation"] == "PICK":
            start = op["initial_state"]["positions"][name]
            assert pos[name][2] > start[2] + 30.0, (op["name"], start, pos[name])  # lifted
        carried += 1
    assert carried >= 2 * sum(s.kind == "pick" for s in sc.demonstration)
