"""Change-detector (Sec. III-D1) and guided visual search (Sec. III-E, Fig. 6)."""

import numpy as np
import pytest

from perception.vision.vfd.base import Region3D
from perception.vision.vfd.change import ChangeDetector
from perception.vision.vfd.resources import VisionResources
from perception.vision.vfd.search import SilFinder, snapshot_region, visual_search

from .helpers import CAMS, Film, block, dist, hand

BRICK = (30.0, 30.0, 50.0)
OTHERS = [block(-200, 300), block(200, 80, (120, 100, 10))]
T = (40.0, 220.0)  # where the target lies


def _pick():
    """Start: brick on the table, hand above. End: brick and hand gone upwards."""
    b = block(*T)
    return [b, *hand(T[0], T[1], 120)], [*hand(T[0], T[1], 260, 32), block(T[0], T[1], BRICK, 210)]


def _place():
    """Start: hand carrying the brick above the spot. End: brick on the table, hand above."""
    start = [*hand(T[0], T[1], 140, 32), block(T[0], T[1], BRICK, 115)]
    end = [block(*T), *hand(T[0], T[1], 100)]
    return start, end


def _touch():
    """Hand comes down beside the brick and leaves: no change of the brick."""
    b = block(*T)
    return [b, *hand(T[0], T[1], 120)], [b, *hand(T[0], T[1], 40)]


def _place_on_block():
    """A brick set onto a plate: the region just above the plate."""
    plate = block(T[0], T[1], (120, 100, 10))
    start = [plate, *hand(T[0], T[1], 120, 32), block(T[0], T[1], BRICK, 95)]
    end = [plate, block(T[0], T[1], BRICK, 10), *hand(T[0], T[1], 60)]
    return start, end


CASES = [  # (id, scenes, snapshot region, expected)
    ("pick-vanished", _pick, Region3D.around((T[0], T[1], 25), (35, 35, 55)), "vanished"),
    ("place-appeared", _place,  # the table spot the search found: region just above it
     snapshot_region(Region3D.around((T[0], T[1], -0.5), (30, 30, 1)), BRICK), "appeared"),
    ("touch-nochange", _touch, Region3D.around((T[0], T[1], 25), (35, 35, 55)), "nochange"),
    ("place-on-block-appeared", _place_on_block,
     snapshot_region(Region3D.around((T[0], T[1], 5), (120, 100, 10)), BRICK), "appeared"),
]


@pytest.mark.parametrize("make,region,expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_change_detector_classifies_pick_place_touch(make, region, expected):
    start, end = make()
    film, res = Film(), VisionResources()
    cd = ChangeDetector(CAMS, res)
    cd.attention(region)
    cd.snapshot(film.shoot(OTHERS + start))
    assert cd.compare(film.shoot(OTHERS + end)) == expected
    if expected != "nochange":
        assert cd.found()
        assert dist(cd.target()[:2], T) < 15.0


def test_snapshot_region_follows_fig6():
    target = Region3D.around((0, 200, 25), (30, 30, 50))
    assert np.allclose(snapshot_region(target).center, (0, 200, 25))
    above = snapshot_region(target, (40, 40, 20))
    assert np.isclose(above.lo[2], 50) and np.isclose(above.hi[2], 70)


def test_visual_search_finds_a_block_under_the_empty_hand():
    film, res = Film(), VisionResources()
    frame = film.shoot(OTHERS + [block(*T), *hand(T[0], T[1], 110)])
    r = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 110))
    assert r.found and r.cycles >= 1
    assert dist(r.position[:2], T) < 15 and 0 < r.position[2] < 55


def test_visual_search_finds_the_support_under_a_held_block():
    film, res = Film(), VisionResources()
    plate = block(T[0], T[1], (120, 100, 10))
    frame = film.shoot([plate, block(T[0], T[1], BRICK, 60), *hand(T[0], T[1], 85, 32)])
    r = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 85), held_size=BRICK,
                      held_center=(T[0], T[1], 85))
    assert r.found
    assert r.position[2] < 30  # the plate, not the held brick


def test_visual_search_gives_up_over_the_bare_table_within_the_cycle_limit():
    film, res = Film(), VisionResources()
    frame = film.shoot(OTHERS + hand(T[0], T[1], 250))
    r = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 250))
    assert not r.found and r.cycles == 4 and len(r.regions) == 5
    low = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 60))
    assert not low.found and low.cycles == 1  # the table is one step away


def test_snapshots_are_values_that_can_be_judged_later():
    start, end = _pick()
    film, res = Film(), VisionResources()
    cd = ChangeDetector(CAMS, res)
    cd.attention(Region3D.around((T[0], T[1], 25), (35, 35, 55)))
    first = cd.take(film.shoot(OTHERS + start))
    last = cd.take(film.shoot(OTHERS + end))
    assert cd.judge(first, last) == "vanished"
    assert cd.judge(last, first) == "appeared"
    assert cd.judge(first, first) == "nochange"
    cd.attention(Region3D.around((0, 100, 25), (35, 35, 55)))
    with pytest.raises(ValueError):
        cd.judge(first, cd.take(film.shoot(OTHERS)))


def test_visual_search_with_a_held_block_over_the_bare_table_finds_nothing():
    film, res = Film(), VisionResources()
    frame = film.shoot([block(T[0], T[1], BRICK, 30), *hand(T[0], T[1], 55, 32)])
    r = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 55), held_size=BRICK,
                      held_center=(T[0], T[1], 55))
    assert not r.found  # the held block itself, hanging over the place, is not a target


def test_visual_search_under_the_hand_relies_on_the_side_view():
    # From above, the palm covers the default region (it has the hand's size), so the
    # silhouette is located on the side view line at the region's depth (not stereo).
    film, res = Film(), VisionResources()
    frame = film.shoot([block(*T), *hand(T[0], T[1], 90)])
    r = visual_search(SilFinder(CAMS, res), frame, (T[0], T[1], 90))
    assert r.found and r.stereo is False and r.cycles == 1
    assert dist(r.position[:2], T) < 10 and 0 < r.position[2] < 50


@pytest.mark.parametrize("noise", [8.0, 16.0], ids=["4x", "8x"])
@pytest.mark.parametrize("make,region,expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_change_detector_holds_at_high_pixel_noise(make, region, expected, noise):
    """Gray-level noise flips pixels across the dark/object cut (40 levels above the table)
    both ways, so the net changed area stays near zero: 4x and 8x noise change no result."""
    start, end = make()
    for seed in range(3):
        film = Film(noise=noise, seed=seed)
        cd = ChangeDetector(CAMS, VisionResources())
        cd.attention(region)
        cd.snapshot(film.shoot(OTHERS + start))
        assert cd.compare(film.shoot(OTHERS + end)) == expected
        assert max(cd.changed_fraction.values()) < 0.02 or expected != "nochange"


def _settled(first):
    """``first`` with its block's top row in the side view gone dark: what a block lowered
    by a pixel shows when it is already nearly on its spot (a robot sets it down slowly)."""
    import dataclasses

    side = first.pixels["side"].copy()
    rows = np.flatnonzero((side > 100).any(axis=1))
    side[rows[0]] = np.where(side[rows[0]] > 100, 0, side[rows[0]])
    return dataclasses.replace(first, pixels={**first.pixels, "side": side})


# A place's threshold is what the carried block can still add (tiny when it is nearly
# down); a vanish keeps the object's own share (ChangeNode.compare sets both).
# (id, scenes, low appeared threshold, vanish threshold, expected)
VANISH = [
    pytest.param("settle", 0.002, None, "vanished", id="settled-one-threshold-reads-vanished"),
    pytest.param("settle", 0.002, 0.05, "nochange", id="settled-vanish-threshold-nochange"),
    pytest.param("pick", 0.002, 0.05, "vanished", id="real-vanish-still-seen"),
    pytest.param("place", 0.002, 0.05, "appeared", id="place-still-appeared"),
]


@pytest.mark.parametrize("scenes,low,vanish,expected", VANISH)
def test_a_vanish_needs_its_own_threshold(scenes, low, vanish, expected):
    film, res = Film(), VisionResources()
    cd = ChangeDetector(CAMS, res)
    region = snapshot_region(Region3D.around((T[0], T[1], -0.5), (30, 30, 1)), BRICK)
    cd.attention(region)
    if scenes == "settle":
        first = cd.take(film.shoot(OTHERS + [block(*T, BRICK)]))
        last = _settled(first)
    else:
        start, end = _pick() if scenes == "pick" else _place()
        first, last = cd.take(film.shoot(OTHERS + start)), cd.take(film.shoot(OTHERS + end))
    cd.area_threshold, cd.vanish_threshold = low, vanish
    assert cd.judge(first, last) == expected
