"""Silhouettes.unshown: a block the views could show on its own, but show dark, is not there
(the monitor's look, docs/monitor.md). One case per row: what the scene holds, which block
is asked about, and the answer."""

import pytest

from perception.vision.camera import default_cameras
from perception.vision.vfd.silhouettes import Silhouettes
from perception.world.render import Renderer
from perception.world.scene import Box

CAMS = default_cameras()
PLATE = ((0.0, 80.0, 10.0), (60.0, 60.0, 20.0))     # a raised plate
BASE = ((0.0, 80.0, 30.0), (20.0, 20.0, 20.0))      # a 20 mm cube on it
TOP = ((0.0, 80.0, 47.5), (15.0, 15.0, 15.0))       # a 15 mm cube on that (round 15, AH)
LOW = ((0.0, 80.0, 10.0), (20.0, 20.0, 20.0))       # the 20 mm cube on the table ...
LOW_TOP = ((0.0, 80.0, 27.5), (15.0, 15.0, 15.0))    # ... and the 15 mm cube on it
FAR = ((0.0, 300.0, 10.0), (20.0, 20.0, 20.0))       # the same at the back of the table,
FAR_TOP = ((0.0, 300.0, 27.5), (15.0, 15.0, 15.0))   # where it shows 6 pixels of its own
APART = ((80.0, 150.0, 15.0), (30.0, 30.0, 30.0))    # a 30 mm cube on its own
TINY = ((0.0, 80.0, 5.0), (10.0, 10.0, 10.0))       # a 10 mm cube ...
CLOAK = ((0.0, 80.0, 30.0), (60.0, 60.0, 60.0))     # ... inside a 60 mm box's silhouette


def _views(boxes, noise):
    scene = [Box("block", c, s) for c, s in boxes]
    return Renderer(CAMS, pixel_noise=noise, seed=3).render(scene)


@pytest.mark.parametrize("scene,box,others,noise,unshown", [
    ([PLATE, BASE, TOP], TOP, [PLATE, BASE], 2.0, False),
    ([PLATE, BASE], TOP, [PLATE, BASE], 2.0, True),
    ([PLATE, BASE, TOP], TOP, [PLATE, BASE], 4.0, False),
    ([PLATE, BASE], TOP, [PLATE, BASE], 4.0, True),
    ([LOW, LOW_TOP], LOW_TOP, [LOW], 2.0, False),
    ([LOW], LOW_TOP, [LOW], 2.0, True),
    # under OWN_PX pixels of its own: not judged here (the monitor's other checks, the
    # structure's wrong pixels, report it gone: docs/monitor.md)
    ([FAR], FAR_TOP, [FAR], 2.0, False),
    ([BASE, APART], APART, [BASE], 2.0, False),
    ([BASE], APART, [BASE], 2.0, True),
    ([BASE], APART, [], 2.0, True),
    ([CLOAK], TINY, [CLOAK], 2.0, False),  # no pixel of its own: not judged
], ids=["raised-cube-on-cube-there", "raised-cube-on-cube-taken",
        "raised-cube-on-cube-there-pixel4", "raised-cube-on-cube-taken-pixel4",
        "cube-on-cube-there", "cube-on-cube-taken", "far-cube-on-cube-not-judged",
        "cube-apart-there", "cube-apart-taken", "cube-apart-taken-alone",
        "hidden-cube-not-judged"])
def test_unshown(scene, box, others, noise, unshown):
    views = _views(scene, noise)
    assert Silhouettes(CAMS, views).unshown(box, others) is unshown
