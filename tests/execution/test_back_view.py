"""The execution workspace's third view finds a block taken from where no other view sees.

Helper round 22 (f03, f04): a table's leg under its top and behind a front leg, taken
away once the top was on. The top and side views pose the table whole, the top stays
level on three legs, and the cameras' verdict was true while the simulator's was false:
no detection, no repair, exit 0 without a spare. The back camera
(``perception.vision.camera.back_camera``) shows the leg's spot empty
(``objects_back.vacant``): the leg is missing, a spare replaces it, or the run ends
naming it.
"""

import numpy as np
import pytest

from perception.vision.camera import back_camera
from perception.vision.vfd.objects_back import vacant
from perception.world.render import Renderer
from perception.world.scene import Box


def test_a_hidden_leg_taken_away_is_replaced_by_the_spare(execute_data):
    code, report, err = execute_data("table-back-leg-removed-spare")
    assert code == 0, (err, report.get("failure"))
    assert [f["kind"] for f in report["faults"]] == ["remove"]
    assert report["monitor"]["detections"] and report["monitor"]["repairs"]
    assert report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_hidden_leg_taken_away_without_a_spare_ends_the_run_naming_it(execute_data):
    code, report, err = execute_data("table-back-leg-removed-no-spare")
    assert code == 1, err
    assert report["failure"].startswith("execution: 'l3' (execute.objects 'd') (shape leg) "
                                        "is gone")
    assert report["verification"] == {"cameras": False, "ground_truth": False}


LEG = (30.0, 30.0, 50.0)
TOP = Box("block", (0.0, 200.0, 60.0), (160.0, 120.0, 20.0), name="top")
LEGS = {name: Box("block", (x, y, 25.0), LEG, name=name) for name, x, y in
        [("l1", -50.0, 160.0), ("l2", 50.0, 160.0), ("l3", 50.0, 240.0),
         ("l4", -50.0, 240.0)]}


@pytest.mark.parametrize("gone, asked, empty", [
    pytest.param(None, "l4", False, id="the leg is there"),
    pytest.param("l4", "l4", True, id="the back-left leg taken away"),
    pytest.param("l2", "l2", True, id="the front-right leg taken away"),
    pytest.param("l1", "l1", False,
                 id="the front-left leg taken: behind l3 from there, undecided (the side "
                    "camera sees it)"),
    pytest.param("l4", "l1", False, id="another leg taken"),
])
def test_which_spots_the_back_view_shows_empty(gone, asked, empty):
    scene = [TOP] + [b for n, b in LEGS.items() if n != gone]
    cam = back_camera()
    img = Renderer({"back": cam}, pixel_noise=4.0, seed=3).render(scene)["back"]
    others = [(TOP.center, TOP.size)] + [(b.center, b.size) for n, b in LEGS.items()
                                         if n != asked]
    assert vacant(cam, img, LEGS[asked].center, LEG, others) is empty


def test_too_small_a_view_decides_nothing():
    """A 10 mm cube behind others shows a few pixels: never called gone on so little."""
    cam = back_camera()
    img = np.zeros((cam.size[1], cam.size[0]), np.uint8)
    assert not vacant(cam, img, (0.0, 200.0, 5.0), (10.0, 10.0, 10.0),
                      [((8.0, 208.0, 20.0), (40.0, 40.0, 40.0))])
