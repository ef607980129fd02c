"""Table I: the external interface every VFD offers an ENV-node, row by row."""

import numpy as np
import pytest

from perception.vision.vfd.base import Region3D
from perception.vision.vfd.resources import VisionResources
from perception.vision.vfd.search import SilFinder

from .helpers import CAMS, Film, block

BRICK_AT = (40.0, 220.0)
REGION = Region3D.around((BRICK_AT[0], BRICK_AT[1], 25.0), (40.0, 40.0, 55.0))
EMPTY = Region3D.around((-200.0, 300.0, 25.0), (40.0, 40.0, 55.0))


def _frames(n=6):
    """``n`` noisy frames of a brick on the table."""
    film = Film()
    return [film.shoot([block(*BRICK_AT)]) for _ in range(n)]


def _row_attention():
    """attention: the 3-D region is projected into one window per view."""
    res = VisionResources()
    sf = SilFinder(CAMS, res)
    sf.attention(REGION)
    assert res.in_use == 2  # one window per view (two MFDs)
    (w,) = sf.windows["side"]
    u, v = CAMS["side"].project(np.array([REGION.center]))[0]
    assert w.x0 <= u < w.x1 and w.y0 <= v < w.y1
    sf.attention(EMPTY)  # re-aiming reuses the windows
    assert res.in_use == 2 and not w.x0 <= u < w.x1


def _row_srate():
    """srate: only every n-th frame is processed."""
    sf = SilFinder(CAMS, VisionResources())
    sf.attention(REGION)
    sf.srate(3)
    sf.start()
    seen = []
    for f in _frames():
        sf.update(f)
        seen.append(sf.found())
    assert seen == [True, False, False, True, False, False]  # frames 0 and 3 only


def _row_start():
    """start: nothing is detected before it."""
    sf = SilFinder(CAMS, VisionResources())
    sf.attention(REGION)
    frames = _frames(2)
    sf.update(frames[0])
    assert not sf.found()  # not started yet
    sf.start()
    sf.update(frames[1])
    assert sf.found()


def _row_stop():
    """stop: nothing is detected after it."""
    sf = SilFinder(CAMS, VisionResources())
    sf.attention(REGION)
    sf.start()
    sf.stop()
    sf.update(_frames(1)[0])
    assert not sf.found() and sf.target() is None


def _row_found():
    """found: true once per detection (since the last query)."""
    sf = SilFinder(CAMS, VisionResources())
    sf.start()
    sf.attention(EMPTY)
    sf.update(_frames(1)[0])
    assert not sf.found()
    sf.attention(REGION)
    sf.update(_frames(1)[0])
    assert sf.found() and not sf.found()  # "since last query"


def _row_target():
    """target: the 3-D position of what was found."""
    sf = SilFinder(CAMS, VisionResources())
    sf.attention(REGION)
    sf.start()
    sf.update(_frames(1)[0])
    assert np.linalg.norm(sf.target()[:2] - np.array(BRICK_AT)) < 10.0


def _row_reset():
    """reset: the detected state is cleared."""
    sf = SilFinder(CAMS, VisionResources())
    sf.attention(REGION)
    sf.start()
    sf.update(_frames(1)[0])
    sf.reset()
    assert sf.target() is None and not sf.found()


def _row_free():
    """free: the windows go back to the resource manager."""
    res = VisionResources()
    sf = SilFinder(CAMS, res)
    sf.attention(REGION)
    sf.free()
    assert res.in_use == 0 and not sf.running


ROWS = [("attention", _row_attention), ("srate", _row_srate), ("start", _row_start),
        ("stop", _row_stop),
        ("found", _row_found), ("target", _row_target), ("reset", _row_reset),
        ("free", _row_free)]


@pytest.mark.parametrize("check", [r[1] for r in ROWS],
                         ids=[f"TableI-row{i + 1}-{r[0]}" for i, r in enumerate(ROWS)])
def test_table_i_interface(check):
    check()
