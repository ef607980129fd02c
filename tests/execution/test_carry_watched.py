"""A block dropped on its way is noticed even when it lands on its goal (issue #13, drops).

Helper round 22 (f13, f18): a beam and a plate let go halfway through their
transfers landed on their goals within the position tolerance; the look after the
ACHIEVE found the plan's state, the robot watch recognized the usual place, and the
drop went undetected. While the robot's jaws are closed on a block (its own sense:
the jaw width at the last close-hand), the side and back views are asked whether the
space just above its fingertips is still lit (``perception.vision.vfd.held``).
"""

import numpy as np
import pytest

from perception.vision.camera import back_camera, default_cameras
from perception.vision.vfd.held import jaw_space, jaws_empty
from perception.world.hand import TIP, Gripper
from perception.world.render import Renderer
from perception.world.scene import Box


def test_a_drop_that_lands_on_its_goal_is_detected(execute_data):
    code, report, err = execute_data("plate-dropped-onto-its-goal")
    assert code == 0, err
    (fault,) = report["faults"]
    drops = [d for d in report["monitor"]["detections"] if d["kind"] == "drop"]
    assert len(drops) == 1 and drops[0]["object"] == "pl"
    assert fault["t"] <= drops[0]["t"] <= fault["t"] + 0.5
    assert report["verification"] == {"cameras": True, "ground_truth": True}


@pytest.mark.parametrize("size, axis", [
    pytest.param((40.0, 40.0, 40.0), 0, id="cube-x-jaws"),
    pytest.param((40.0, 40.0, 40.0), 1, id="cube-y-jaws"),
    pytest.param((12.0, 12.0, 12.0), 0, id="12mm-cube"),
    pytest.param((160.0, 30.0, 15.0), 1, id="plank-across-its-width"),
])
@pytest.mark.parametrize("held", [True, False], ids=["held", "dropped"])
def test_the_jaws_are_seen_empty_only_when_the_block_is_gone(size, axis, held):
    grip = (30.0, 220.0, 160.0)
    g = Gripper(grip, opening=size[axis], kind="arm")
    g.axis = axis
    g.fingers = g._make_fingers()
    g._place_fingers(0.0)
    own = [(b.center, b.size) for b in g.boxes()]
    centre_z = grip[2] - TIP - 1.0 + size[2] / 2.0  # fingertips 1 mm above its bottom
    scene = list(g.boxes()) + ([Box("block", (grip[0], grip[1], centre_z), size)]
                               if held else [])
    cams = dict(default_cameras()) | {"back": back_camera()}
    images = Renderer(cams, pixel_noise=8.0, seed=5).render(scene)
    images = {k: v for k, v in images.items() if k != "top"}  # the palm hides it there
    space = jaw_space(grip, axis, size[axis], TIP)
    assert jaws_empty(cams, images, space, own) is (not held)


def test_nothing_in_view_decides_nothing():
    cam = default_cameras()["side"]
    img = np.zeros((cam.size[1], cam.size[0]), np.uint8)
    space = ((0.0, 200.0, 100.0), (6.0, 6.0, 6.0))
    assert jaws_empty({"side": cam}, {"side": img}, space, [space]) is None
