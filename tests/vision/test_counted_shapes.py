"""A block measured between two shapes of one footprint, settled by the count of blocks
(objects_restack._one; helper round 19, r69 and r83).

The side view reads heights to about a pixel, 3.3 mm at the back of the table: a 30 mm
cube there measured 33.2 mm and was named the listed 35 mm shape, and the teach object
it was had no counterpart. Where the count (the naming hint in the teach workspace,
the plan in the execution one) lacks a shape and has a surplus of another, a surplus
block within RENAME_PX of the missing shape on every side is read as it.
"""

from __future__ import annotations

import numpy as np
import pytest

from perception.vision.camera import default_cameras
from perception.vision.vfd.objects_match import FoundObject
from perception.vision.vfd.objects_restack import restack

SHAPES = {"c30": (30.0, 30.0, 30.0), "c35": (30.0, 30.0, 35.0), "slab": (60.0, 30.0, 30.0)}


def _c35(x: float, height: float, y: float = 320.0) -> FoundObject:
    return FoundObject("c35", (x, y, height / 2.0), (30.4, 30.2, height), 0.5)


@pytest.mark.parametrize(("middle", "needs", "want"), [
    (33.2, {"c35": 2, "c30": 1}, ["c35", "c30", "c35"]),   # r83: read a pixel high
    (32.6, {"c35": 2, "c30": 1}, ["c35", "c30", "c35"]),   # r69
    (33.2, {"c35": 3}, ["c35", "c35", "c35"]),             # the count wants three 35s
    (36.0, {"c35": 2, "c30": 1}, ["c35", "c35", "c35"]),   # 6 mm off the 30: not it
    (33.2, {"c35": 2, "slab": 1}, ["c35", "c35", "c35"]),  # a missing shape of another size
], ids=["read-a-pixel-high", "read-2.6mm-high", "count-satisfied", "too-far-from-the-missing",
        "missing-shape-another-footprint"])
def test_a_surplus_block_near_a_missing_shape_is_read_as_it(middle, needs, want):
    cam = default_cameras()["side"]
    found = [_c35(-220.0, 35.6), _c35(-100.0, middle), _c35(100.0, 36.3)]
    out = restack(cam, np.zeros((256, 256), np.uint8), found, needs, SHAPES)
    assert [f.shape for f in sorted(out, key=lambda f: f.position[0])] == want
    renamed = [f for f in out if f.shape == "c30"]
    for f in renamed:  # the shape's own size, standing where the block was measured
        assert f.size == (30.0, 30.0, 30.0) and f.position[2] == 15.0
