"""The robot's wrist turns (design.md "Robot"): jaws along y in the x-z simulation.

A grasp along y is a grasp — the same force-limited joints hold the block, so it
can slip — and contacts along y, which pymunk does not have, push blocks ahead.
"""

import pytest

from perception.world.hand import Gripper, GripperGeometry
from perception.world.physics import World
from perception.world.scenario import ObjectSpec

CUBE = (40.0, 40.0, 40.0)


def _world(*blocks):
    """Cubes named by their (x, y) on the table; the first is 'a', then 'b', 'c'."""
    specs = [ObjectSpec(n, "cube", CUBE, (x, y, 20.0), ("table",))
             for n, (x, y) in zip("abc", blocks, strict=False)]
    w = World(specs)
    w.settle(0.3)
    return w


def _grip(w, axis=1, strength=25.0):
    """Lower jaws along x (0) or y (1) around 'a', opened 12 mm wider, and close them."""
    x, y, _ = w.positions()["a"]
    g = w.add_gripper(Gripper((x, y, 150.0), opening=52.0, kind="arm",
                              geometry=GripperGeometry(grip_strength=strength), y_contacts=True))
    g.turn(axis)
    g.move_to((x, y, 31.0))
    w.settle(1.0)
    g.close()
    w.settle(1.0)
    return g


def test_jaws_along_y_grip_between_close_neighbours_along_x():
    w = _world((0.0, 200.0), (44.0, 200.0))  # 4 mm gap along x: no x-finger fits
    g = _grip(w)
    assert g.holding == "a" and g.opening == pytest.approx(41.0, abs=1.0)
    g.move_to((0.0, 200.0, 120.0))
    w.settle(1.0)
    pos = w.positions()
    assert pos["a"][2] == pytest.approx(109.0, abs=1.0)
    assert pos["b"] == pytest.approx((44.0, 200.0, 20.0), abs=0.2)  # untouched


def test_a_grasp_along_y_is_force_limited_and_slips():
    w = _world((0.0, 200.0))
    g = _grip(w, strength=0.5)  # the joints hold half the block's weight
    assert g.holding == "a"
    g.move_to((0.0, 200.0, 120.0))
    w.settle(1.0)
    assert w.positions()["a"][2] < 25.0  # it slipped out of the lift


def test_a_held_block_moved_along_y_pushes_the_block_it_meets():
    w = _world((0.0, 200.0), (0.0, 250.0))  # 10 mm apart along y
    g = _grip(w, axis=0)  # the jaws across y: the held block leads
    g.move_to((0.0, 200.0, 22.0))
    w.settle(0.5)
    g.move_to((0.0, 215.0, 22.0))  # 15 mm along y: 5 mm into 'b'
    w.settle(1.0)
    pos = w.positions()
    assert pos["a"][1] == pytest.approx(215.0, abs=0.5)
    assert pos["b"][1] == pytest.approx(255.0, abs=0.5)  # pushed ahead, by 5 mm
    assert pos["b"][0] == pytest.approx(0.0, abs=0.2)  # no x-z kick
    assert w.angles()["b"] == pytest.approx(0.0, abs=0.01)


def test_the_wrist_turns_only_with_empty_jaws():
    w = _world((0.0, 200.0))
    g = _grip(w)
    with pytest.raises(ValueError, match="empty jaws"):
        g.turn(0)
