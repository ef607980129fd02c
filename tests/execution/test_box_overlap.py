"""lbw_engine.model.geometry: how far two boxes overlap, as a table (one case per row).

``overlap`` with a negative tolerance asks whether two boxes come within that distance
of each other (the set-aside spot's jaw clearance, do/clearing.py); ``depth`` is how
deep they interpenetrate, never negative. A refactor that read ``overlap`` through the
clamped ``depth`` made every spot on the table look occupied (stop 36, caught by CI).
"""

import pytest

from lbw_engine.model.geometry import depth, overlap

CUBE = (30.0, 30.0, 30.0)

# (id, centre of the second cube, tol, overlap?, depth)
ROWS = [
    ("into by 10 mm along x", (20.0, 0.0, 0.0), 1.0, True, 10.0),
    ("touching along x", (30.0, 0.0, 0.0), 0.0, False, 0.0),
    ("5 mm apart, clearance 8", (35.0, 0.0, 0.0), -8.0, True, 0.0),
    ("5 mm apart, clearance 4", (35.0, 0.0, 0.0), -4.0, False, 0.0),
    ("into by 2 mm, tolerance 3", (28.0, 0.0, 0.0), 3.0, False, 2.0),
    ("into on x, apart on y", (20.0, 40.0, 0.0), 1.0, False, 0.0),
]


@pytest.mark.parametrize("other, tol, overlapping, deep", [r[1:] for r in ROWS],
                         ids=[r[0] for r in ROWS])
def test_overlap_and_depth(other, tol, overlapping, deep):
    assert overlap((0.0, 0.0, 0.0), CUBE, other, CUBE, tol=tol) is overlapping
    assert depth((0.0, 0.0, 0.0), CUBE, other, CUBE) == pytest.approx(deep)
