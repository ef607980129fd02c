"""Object-finder (Sec. III-B): shapes named and positioned from the two views."""

import numpy as np
import pytest

from perception.vfd_objects import ObjectFinder
from perception.vfd_resources import VisionResources

from .helpers import CAMS, Film, block

SHAPES = {"brick": [30, 30, 50], "plate": [120, 100, 10], "cube": [40, 40, 40],
          "beam": [100, 20, 20]}


def _layout(name):
    b = {"brick": (30, 30, 50), "plate": (120, 100, 10), "cube": (40, 40, 40),
         "beam": (100, 20, 20)}
    if name == "apart":
        return [("brick", block(-150, 200, b["brick"])), ("brick", block(-100, 320, b["brick"])),
                ("plate", block(150, 220, b["plate"])), ("cube", block(-240, 60, b["cube"])),
                ("beam", block(200, 60, b["beam"]))]
    if name == "corners":
        return [("brick", block(-270, 30, b["brick"])), ("cube", block(270, 370, b["cube"])),
                ("brick", block(270, 30, b["brick"])), ("cube", block(-270, 370, b["cube"]))]
    if name == "stack":  # a brick resting on a plate
        return [("plate", block(100, 200, b["plate"])), ("brick", block(110, 190, b["brick"], 10)),
                ("cube", block(-150, 150, b["cube"]))]
    raise KeyError(name)


@pytest.mark.parametrize("layout", ["apart", "corners", "stack"])
def test_object_finder_names_and_positions_every_block(layout):
    truth = _layout(layout)
    res = VisionResources()
    found = ObjectFinder(CAMS, res).find(Film(seed=4).shoot([b for _, b in truth]), SHAPES)
    assert len(found) == len(truth)
    assert res.in_use == 0  # windows are returned
    for shape, box in truth:
        near = min(found, key=lambda f: np.linalg.norm(np.subtract(f.position, box.center)))
        assert near.shape == shape
        assert np.linalg.norm(np.subtract(near.position, box.center)) < 5.0
        assert np.abs(np.subtract(near.size, box.size)).max() < 6.0


def test_object_finder_on_an_empty_table_finds_nothing():
    det = ObjectFinder(CAMS, VisionResources())
    assert det.find(Film().shoot([]), SHAPES) == []
    assert not det.found()
