"""Coplanar-detector (Fig. 5): aligned faces are coplanar, offset ones are not."""

import pytest

from perception.vision.vfd.base import Region3D
from perception.vision.vfd.coplanar import CoplanarDetector
from perception.vision.vfd.resources import VisionResources
from perception.world.scene import Box

from .helpers import CAMS, Film, block

BRICK = (30.0, 30.0, 50.0)


def _pair(x, y, dy, dx=0.0):
    """Two bricks side by side along x (touching unless dx), the second shifted by dy."""
    a = block(x, y, BRICK)
    b = block(x + 30.0 + dx, y + dy, BRICK)
    return a, b


def _region(box):
    """The 3-D region a box occupies (what the environment model would pass)."""
    return Region3D.around(box.center, box.size)


CASES = [  # (id, x, y, dy, dx, face, coplanar)
    ("north-aligned-far", -100, 320, 0, 0, "north", True),
    ("north-offset-12mm-far", -100, 320, 12, 0, "north", False),
    ("south-aligned-near", 60, 90, 0, 0, "south", True),
    ("south-offset-10mm-near", 60, 90, -10, 0, "south", False),
    ("north-aligned-with-gap", 150, 250, 0, 15, "north", True),
    ("north-offset-8mm-near", -220, 60, 8, 0, "north", False),
]


@pytest.mark.parametrize("x,y,dy,dx,face,coplanar", [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_coplanar_detector(x, y, dy, dx, face, coplanar):
    a, b = _pair(x, y, dy, dx)
    frame = Film().shoot([a, b])
    det = CoplanarDetector(CAMS, VisionResources())
    assert det.check(frame, _region(a), _region(b), face) is coplanar
    assert abs(det.step_mm - (-dy if face in ("north", "south") else 0.0)) < 4.5


def test_east_faces_of_blocks_stacked_along_y():
    a = block(0, 150, BRICK)
    b = block(0, 180, BRICK)
    c = block(14, 180, BRICK)
    det = CoplanarDetector(CAMS, VisionResources())
    assert det.check(Film().shoot([a, b]), _region(a), _region(b), "east")
    assert not det.check(Film().shoot([a, c]), _region(a), _region(c), "east")


def test_coplanar_faces_lists_the_aligned_sides():
    a, b = _pair(-100, 250, 0)
    det = CoplanarDetector(CAMS, VisionResources())
    assert det.coplanar_faces(Film().shoot([a, b]), _region(a), _region(b)) == ["north", "south"]
    a, b = _pair(-100, 250, 10)
    assert det.coplanar_faces(Film().shoot([a, b]), _region(a), _region(b)) == []


def test_a_palm_over_the_faces_makes_them_unmeasurable():
    """The hand above two aligned blocks gives its own outline: not a coplanarity (ALIGN waits)."""
    a = block(0, 150, BRICK)
    b = block(0, 180, BRICK)
    palm = Box("hand", (5.0, 165.0, 150.0), (50.0, 50.0, 30.0))
    det = CoplanarDetector(CAMS, VisionResources())
    assert det.check(Film().shoot([a, b]), _region(a), _region(b), "east")
    assert not det.check(Film().shoot([a, b, palm]), _region(a), _region(b), "east")
    assert det.step_mm is None
    far = Box("hand", (150.0, 300.0, 150.0), (50.0, 50.0, 30.0))  # elsewhere: measurable
    assert det.check(Film().shoot([a, b, far]), _region(a), _region(b), "east")
