"""Generated 4x-noise scenarios whose hand was lost mid-motion (`lbw bench`, level 4x).

At pixel noise std 8 a lone noise cell could pass the motion-detector's floor in
a view where the slowly moving hand barely changed the image; the triangulated
point fell more than 120 mm from the tracked hand, the hand-tracker was
re-placed onto empty table, lost the hand within four frames and the task ended
with :Disappeared. Now the motion-detector needs a seed cell above the measured
sensor noise in each view (perception.vision.vfd.motion).
"""

from __future__ import annotations

import numpy as np
import pytest

from perception.vision.camera import default_cameras
from perception.vision.vfd.motion import MotionDetector
from perception.vision.vfd.resources import VisionResources
from perception.world.demonstrator import Demonstration
from perception.world.generator import generate
from perception.world.stream import demonstration_frames

from .generated import assert_sequence, watch_generated

CASES = {
    # lost at 43 s while lowering a held block: the place ended the task
    "seed1005-lost-mid-place": 1005,
    # lost at 50.6 s after a touch: 8 of 15 operations
    "seed1023-lost-after-touch": 1023,
    # 8 of 31 operations
    "seed1074-lost-mid-pick": 1074,
}


@pytest.mark.parametrize("seed", list(CASES.values()), ids=list(CASES))
@pytest.mark.heavy
def test_hand_kept_through_the_whole_4x_demonstration(seed):
    sc, _, actions = watch_generated(seed, "4x")
    assert_sequence(sc, actions)


def test_motion_points_stay_on_the_hand_at_4x_noise():
    """The demonstrator's hand position is read here only to measure the detector."""
    sc = generate(1005, "4x").scenario()
    cams = default_cameras()
    demo = Demonstration(sc)
    md = MotionDetector(cams, VisionResources())
    md.start()
    far = []
    for frame in demonstration_frames(sc, cams, demonstration=demo):
        md.update(frame)
        if md.found() and demo.hand.present:
            hand = np.asarray(demo.hand.position, float)
            off = float(np.linalg.norm(md.target() - hand))
            # the hand leaving past the image border is seen only in part
            if off > 120.0 and abs(hand[0]) < 330.0:
                far.append((round(frame.t, 2), round(off)))
    assert md.sensor_noise == pytest.approx(8.0 * np.sqrt(2.0), rel=0.2)
    assert far == []


def test_a_hand_hesitating_as_it_lifts_off_a_pillar_is_still_leaving():
    """Bench seed 1017 (pillars, 4x): after setting a 112 mm pillar down, the hand paused
    three times on its way up; at each pause the pillar under it was searched for and
    found, giving an extra REACH and NO-OP. An empty hand that has not come down from its
    highest point since its Transfer began, above where it began, is not arriving."""
    sc, _, actions = watch_generated(1017, "4x", family="pillars")
    assert_sequence(sc, actions)

