"""Naming found objects after the teach workspace (design.md, actions.json ``objects``).

A found block takes the teach name of the nearest block of its shape within
NAME_RADIUS in x, y; nearest is measured in x, y and z: blocks of one shape stacked on
each other share x and y (bench seed 1210, stacked-start: the lower cube took the upper
one's name, and the plan's relations came out swapped although the sequence and
execution were right).
"""

from types import SimpleNamespace

import pytest

from perception.vision.envnodes.objects import NAME_RADIUS, ObjectFinderNode

STACK = {"low": ("cube", (0.0, 200.0, 20.0)), "up": ("cube", (0.0, 200.0, 60.0)),
         "post": ("brick", (100.0, 200.0, 25.0))}

ROWS = [
    # found shape, found centre, names already taken, expected name
    pytest.param("cube", (1.0, 201.0, 21.0), set(), "low", id="lower-of-stack"),
    pytest.param("cube", (-2.0, 199.0, 62.0), set(), "up", id="upper-of-stack"),
    pytest.param("cube", (1.0, 201.0, 21.0), {"low"}, "up", id="next-nearest-when-taken"),
    pytest.param("cube", (100.0, 200.0, 25.0), set(), None, id="other-shape-only"),
    pytest.param("brick", (100.0, 200.0 + NAME_RADIUS + 1.0, 25.0), set(), None,
                 id="beyond-radius"),
    # the radius is on x, y: a height misread (a thin pillar's, bench 1267) keeps the name
    pytest.param("brick", (100.0 - NAME_RADIUS / 2, 200.0, 25.0 + 2 * NAME_RADIUS), set(),
                 "post", id="height-misread"),
]


@pytest.mark.parametrize(("shape", "at", "taken", "name"), ROWS)
def test_a_found_block_takes_the_nearest_teach_name(shape, at, taken, name):
    node = SimpleNamespace(names=STACK)
    assert ObjectFinderNode._teach_name(node, shape, at, set(taken)) == name
