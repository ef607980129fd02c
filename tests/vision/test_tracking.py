"""Resource manager, motion-detector and hand-tracker on rendered synthetic scenes."""

import numpy as np
import pytest

from perception.vision.vfd.base import Region3D
from perception.vision.vfd.hand import HandTracker
from perception.vision.vfd.motion import MotionDetector
from perception.vision.vfd.resources import MAX_WINDOWS, ResourceExhausted, VisionResources

from .helpers import CAMS, Film, block, dist, hand

BLOCKS = [block(-150, 200), block(100, 250), block(200, 80, (120, 100, 10))]


def test_resource_manager_refuses_the_33rd_window_and_reuses_freed_ones():
    res = VisionResources()
    wins = [res.allocate("top") for _ in range(MAX_WINDOWS)]
    with pytest.raises(ResourceExhausted):
        res.allocate("side")
    res.free(wins[5])
    assert res.allocate("side").view == "side"
    assert res.in_use == MAX_WINDOWS


def test_a_detector_that_cannot_get_windows_fails_and_holds_none():
    res = VisionResources(max_windows=4)
    with pytest.raises(ResourceExhausted):
        HandTracker(CAMS, res)  # needs 5 windows
    assert res.in_use == 0


def test_windows_count_only_the_pixels_they_read():
    res = VisionResources()
    w = res.allocate("top", (10, 20, 30, 30))
    w.read(np.zeros((256, 256), np.uint8))
    assert res.end_frame() == 200
    coarse = res.allocate("top", (0, 0, 256, 256), step=4)
    coarse.read(np.zeros((256, 256), np.uint8))
    assert res.end_frame() == 64 * 64


def _path(k):
    """A hand moving diagonally and down at about 100 mm/s."""
    t = k / 30.0
    return np.array([-200 + 100 * t, 150 + 30 * np.sin(t), 150 - 13 * t])


def test_motion_detector_finds_the_moving_hand_and_not_a_still_scene():
    film, res = Film(), VisionResources()
    md = MotionDetector(CAMS, res)
    md.start()
    for _ in range(10):
        md.update(film.shoot(BLOCKS + hand(0, 200, 150)))
    assert not md.found()  # noise alone is not motion
    hits = []
    for k in range(30):
        p = _path(k)
        md.update(film.shoot(BLOCKS + hand(*p)))
        if md.found():
            hits.append(dist(md.target()[:2], p[:2]))
    assert len(hits) >= 8  # one sample per 83.5 ms
    assert np.median(hits) < 40.0  # the centre of changed cells is on the hand


def test_hand_tracker_follows_a_moving_hand_within_a_few_mm():
    film, res = Film(), VisionResources()
    md, ht = MotionDetector(CAMS, res), HandTracker(CAMS, res)
    md.start()
    errors, placed = [], False
    for k in range(90):
        p = _path(k)
        frame = film.shoot(BLOCKS + hand(*p))
        md.update(frame)
        if md.found():
            placed |= ht.stimulate(md.target())
        ht.update(frame)
        if ht.position is not None and k > 20:
            errors.append(np.abs(ht.position - p))
        res.end_frame()
    assert placed
    err = np.array(errors)
    assert len(err) > 60
    assert err.mean(axis=0).max() < 3.0 and err.max() < 8.0
    assert dist(ht.velocity, (100, 30 * np.cos(3.0), -13)) < 20.0


def test_hand_tracker_reports_loss_when_the_hand_leaves():
    film, res = Film(), VisionResources()
    ht = HandTracker(CAMS, res)
    ht.place((0, 200, 150))
    for _ in range(3):
        ht.update(film.shoot(BLOCKS + hand(0, 200, 150)))
    assert ht.found() and ht.position is not None
    for _ in range(6):
        ht.update(film.shoot(BLOCKS))
    assert ht.position is None  # the ENV-node's :Disappeared


def test_hand_tracker_is_replaced_when_motion_disagrees_by_more_than_120mm():
    film, res = Film(), VisionResources()
    ht = HandTracker(CAMS, res)
    ht.place((0, 200, 150))
    for _ in range(3):
        ht.update(film.shoot(BLOCKS + hand(0, 200, 150)))
    assert not ht.stimulate((50, 200, 150))
    assert ht.stimulate((200, 100, 150))


def test_a_far_motion_point_replaces_the_tracker_only_where_the_hand_is():
    """Given the frame, a motion centre off the hand (dragged along a carried 180 mm beam,
    issue #12 class 4) leaves a tracking tracker where it is; the hand seen there moves it."""
    film, res = Film(), VisionResources()
    ht = HandTracker(CAMS, res)
    ht.place((0, 200, 150))
    frame = None
    for _ in range(3):
        frame = film.shoot(BLOCKS + hand(0, 200, 150))
        ht.update(frame)
    assert not ht.stimulate((0, 340, 150), frame)
    assert ht.tracking and dist(ht.position, (0, 200, 150)) < 10.0
    moved = film.shoot(BLOCKS + hand(200, 100, 150))
    assert ht.stimulate((200, 100, 150), moved)


def test_attention_projects_a_region_into_both_views():
    from perception.vision.vfd.base import VFD
    res = VisionResources()
    v = VFD(CAMS, res)
    v.attention(Region3D.around((0, 200, 25), (30, 30, 50)))
    (top,), (side,) = v.windows["top"], v.windows["side"]
    assert top.x0 < CAMS["top"].project(np.array([0, 200, 50]))[0][0] < top.x1
    assert side.y0 < CAMS["side"].project(np.array([0, 200, 25]))[0][1] < side.y1
    assert res.in_use == 2
    v.free()
    assert res.in_use == 0


def _reach_and_descend(k, speed):
    """Reach across the table, then come down beside a plate (touching height)."""
    t = k / 30.0 * speed
    if t < 2:
        return np.array([-250 + 150 * t, 150 + 40 * t, 180.0])
    return np.array([50.0, 230.0, max(45.0, 180 - 60 * (t - 2))])


@pytest.mark.parametrize("carry,noise,speed", [(False, 2.0, 1.0), (False, 5.0, 2.0),
                                               (True, 2.0, 1.0), (True, 5.0, 2.0)],
                         ids=["empty-noise2", "empty-noise5-fast", "carrying-noise2",
                              "carrying-noise5-fast"])
def test_hand_tracker_near_blocks_while_carrying_and_with_more_noise(carry, noise, speed):
    film, res = Film(noise=noise), VisionResources()
    md, ht = MotionDetector(CAMS, res), HandTracker(CAMS, res)
    md.start()
    scene = [block(-150, 200), block(100, 250), block(40, 180, (120, 100, 10))]
    errors, evidence = [], []
    for k in range(150):
        p = _reach_and_descend(k, speed)
        boxes = scene + hand(*p, 32 if carry else 60)
        if carry:
            boxes.append(block(p[0], p[1], (30, 30, 50), p[2] - 25))
        frame = film.shoot(boxes)
        md.update(frame)
        if md.found():
            ht.stimulate(md.target())
        ht.update(frame)
        if ht.position is not None and k > 30:
            errors.append(dist(ht.position, p))
            evidence.append(ht.holding_evidence)
        res.end_frame()
    assert len(errors) > 110
    assert np.median(errors) < 3.0 and max(errors) < 8.0
    assert bool(np.median(evidence) > 0.5) is carry  # the holder window sees the held block
    assert np.mean(res.history) < 0.10 * 2 * 256 * 256  # windows keep the reads small


@pytest.mark.parametrize("make,need", [(MotionDetector, 2), (HandTracker, 5)],
                         ids=["motion-detector", "hand-tracker"])
def test_detectors_take_all_their_windows_or_none(make, need):
    res = VisionResources()
    hog = [res.allocate("top") for _ in range(MAX_WINDOWS - need + 1)]
    with pytest.raises(ResourceExhausted):
        make(CAMS, res)
    assert res.in_use == len(hog)
    res.free(hog[0])
    det = make(CAMS, res)
    assert res.in_use == MAX_WINDOWS
    det.free()
    assert res.in_use == MAX_WINDOWS - need


@pytest.mark.parametrize("noise", [2.0, 8.0])
def test_motion_detector_measures_the_sensor_noise_of_unclipped_pixels(noise):
    film, res = Film(noise=noise, seed=1), VisionResources()
    md = MotionDetector(CAMS, res)
    md.start()
    for k in range(60):  # a hand moving through: its pixels are a minority
        md.update(film.shoot(BLOCKS + hand(*_path(k % 30))))
    # std of one pixel's change between two buffers: sqrt(2) x the pixel noise
    assert md.sensor_noise == pytest.approx(noise * np.sqrt(2.0), rel=0.25)


def _descend(k):
    """Come straight down at 60 mm/s from 180 mm to a grip 25 mm above the table."""
    return max(25.0, 180.0 - 2.0 * k)


@pytest.mark.parametrize("x,y,axis,front,axis_err", [
    # the jaws close along y, across the side camera's line of sight, at the table's
    # west end: the front finger hides the back one (HandTracker._one_band; bench 1009)
    (-245.0, 105.0, 1, None, 0),
    # an 80 mm wide block stands between the side camera and the hand, 45 mm in front of
    # the grip: it hides the fingertips for the last 30 mm (HandTracker._unhidden; 1013)
    (170.0, 262.0, 0, (169.0, 217.0), 2),
], ids=["y-jaws-at-the-table-end", "fingertips-behind-a-block"])
def test_hand_tracker_keeps_the_grip_where_the_side_view_misleads(x, y, axis, front, axis_err):
    film, res = Film(seed=3), VisionResources()
    ht = HandTracker(CAMS, res)
    ht.place((x, y, 180.0))
    scene = [block(*front, (80.0, 50.0, 50.0))] if front else []
    errors = []
    for k in range(110):
        p = np.array([x, y, _descend(k)])
        ht.update(film.shoot(scene + hand(*p, 40.0, axis)))
        if k > 10:
            errors.append(abs(ht.position[axis_err] - p[axis_err]))
        res.end_frame()
    # x within 2 mm; the height within 8 mm (the palm seen over the block is cut too)
    assert max(errors) < (2.0 if axis_err == 0 else 8.0), max(errors)
