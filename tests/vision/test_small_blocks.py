"""Small blocks and tall pillars (issue #12, class 3): a place is seen, on the right support.

Two detector decisions went wrong for them, each a tolerance fixed in pixels or mm that
does not scale with the object:
- the change-detector asked a place for a third of the block's share of the window,
  though a tall block held above its spot is already in view there, and a block put on a
  block lands in front of its support's bright faces (the place was read as a NO-OP);
- the visual search took the neighbours of a 10 mm cube set down in the gap of a row as
  a bridge's two supports, and a small cube the hand came in over as the support.
"""

import math

import pytest

from lbw_engine.model.env import EnvNode
from lbw_engine.rules import load_rules
from perception.vision.envnodes.change import ChangeNode
from perception.vision.envnodes.hand import HandState, Sight
from perception.vision.envnodes.search import WAIT, SearchNode
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources

from .helpers import CAMS, Film, block, hand

RULES = load_rules()
T = (-140.0, 60.0)


def _pillar():
    """A 17x17x118 pillar held with its foot 70 mm above the spot, then standing there."""
    # (each maker: block size, support top, start scene, end scene[, held x offset])
    size = (17.0, 17.0, 118.0)
    start = [*hand(T[0], T[1], 250, 17), block(T[0], T[1], size, 70)]
    return size, 0.0, start, [block(T[0], T[1], size), *hand(T[0], T[1], 250)]


def _small_on_cube():
    """A 14 mm cube set on a 40 mm cube (it lands in front of the support's top face)."""
    size, cube = (14.0, 14.0, 14.0), block(T[0], T[1], (40.0, 40.0, 40.0))
    start = [cube, *hand(T[0], T[1], 110, 14), block(T[0], T[1], size, 90)]
    return size, 40.0, start, [cube, block(T[0], T[1], size, 40), *hand(T[0], T[1], 110)]


def _pillar_behind():
    """A 13 mm pillar coming in 15 mm beside its spot (foot 40 mm up), set down behind
    another pillar that stands 42 mm in front of it (the side camera looks along +y)."""
    size = (13.0, 13.0, 115.0)
    front = block(T[0], T[1] - 42, size)
    start = [front, *hand(T[0] + 15, T[1], 200, 13), block(T[0] + 15, T[1], size, 40)]
    return size, 0.0, start, [front, block(T[0], T[1], size), *hand(T[0], T[1], 250)], 15.0


@pytest.mark.parametrize("make", [_pillar, _small_on_cube, _pillar_behind],
                         ids=["pillar", "14mm-on-cube", "pillar-behind-pillar"])
@pytest.mark.parametrize("noise", [2.0, 8.0], ids=["nominal", "4x"])
def test_a_place_of_a_small_or_tall_block_is_seen(make, noise):
    size, top, start, end, *off = make()
    node = ChangeNode(HandState(Sight(CAMS), RULES), RULES)
    # The place region of Fig. 6(3), as ChangeNode.region builds it for a held block: over
    # the held block's centre when the motion began, on the support's top.
    x = T[0] + (off[0] if off else 0.0)
    region = Region3D.around((x, T[1], top + size[2] / 2), (size[0] + 50, size[1] + 50, size[2]))
    film, det = Film(noise), node.detector
    det.attention(region)
    load = next(b for b in start if b.kind == "block" and b.center[2] > top + size[2] / 2)
    first = node.carrying(det.take(film.shoot(start)), Region3D.around(load.center, size))
    det.area_threshold = node.threshold(first, size, place=True)
    assert det.judge(first, det.take(film.shoot(end))) == "appeared"


# A 17 mm cube picked from behind a stack of two such cubes standing 40 mm in front of it
# (the side camera looks along +y); the palm hides it from above at the pick's end. Bench
# seed 1157 (small, 2x), whose cube stood here: part of its side outline was hidden, its
# pick changed less of the window than is asked of a cube in plain view, and was read as a
# NO-OP. A stack behind it shows through where it was: lbw bench 1156, a 19 mm cube picked
# from against another, changed 0.096 of the window where 0.12 was asked. (id, the stack's
# (x, y) offset from the cube, whether the pick is missed when asked as much as in view)
AT = (-160.0, 188.0)
PICK_BEHIND = [("stack-in-front", (-3.0, -40.0), True), ("stack-behind", (-3.0, 40.0), False)]


@pytest.mark.parametrize("off,missed", [c[1:] for c in PICK_BEHIND],
                         ids=[c[0] for c in PICK_BEHIND])
def test_a_pick_of_a_small_cube_partly_hidden_in_front_is_seen(off, missed):
    size = (17.0, 17.0, 17.0)
    x, y = AT[0] + off[0], AT[1] + off[1]
    stack = [block(x, y, size), block(x, y, size, 17)]
    start = [*stack, block(*AT, size), *hand(AT[0], AT[1], 40, 40)]
    end = [*stack, block(AT[0], AT[1], size, 60), *hand(AT[0], AT[1], 68, 17)]  # lifted
    node = ChangeNode(HandState(Sight(CAMS), RULES), RULES)
    # the pick region of Fig. 6(3): the target's box grown by PICK_MARGIN_MM
    region = Region3D.around((AT[0], AT[1], size[2] / 2), (size[0] + 16, size[1] + 16,
                                                           size[2] + 16))
    film, det = Film(4.0), node.detector
    det.attention(region)
    first = det.take(film.shoot(start))
    last = det.take(film.shoot(end))
    plain = node.threshold(first, size)
    others = [Region3D.around(b.center, b.size) for b in stack]
    det.area_threshold = node.threshold(first, size, others=others)
    assert det.area_threshold < plain
    assert det.judge(first, last) == "vanished"
    det.area_threshold = plain  # asked as much as of a cube in plain view
    assert (det.judge(first, last) == "nochange") == missed


def test_nothing_appears_where_nothing_was_put():
    size, top, start, _ = _pillar()
    node = ChangeNode(HandState(Sight(CAMS), RULES), RULES)
    region = Region3D.around((T[0], T[1], top + size[2] / 2), (67, 67, size[2]))
    film, det = Film(8.0), node.detector
    det.attention(region)
    first = det.take(film.shoot(start))
    det.area_threshold = node.threshold(first, size, place=True)
    assert det.judge(first, det.take(film.shoot(start))) == "nochange"


def _cube(name, x, y, s=10.0, z0=0.0):
    return EnvNode(name, "Loc", (x, y, z0 + s / 2), (s, s, s))


def _held(x, y, s, z0):
    return Region3D.around((x, y, z0 + s / 2), (s, s, s))


ROW = [_cube("a", 0, 344.5), _cube("b", 0, 373.5)]  # a row of 10 mm cubes, 19 mm apart
PAIR = [_cube("l", 0, 188, 14), _cube("r", 0, 212, 14)]  # 14 mm cubes, 10 mm apart
LEVEL_CASES = [  # (id, level, held box, level top, expected: names, WAIT or None = beside)
    ("10mm-into-gap-of-row", ROW, _held(0, 359, 10, 15), 10.0, None),
    ("10mm-into-gap-off-by-2", ROW, _held(0, 357, 10, 15), 10.0, None),
    ("15mm-across-a-10mm-gap", PAIR, _held(0, 200, 15, 20), 14.0, ("l", "r")),
    ("10mm-on-one-cube", ROW[:1], _held(1, 346, 10, 12), 10.0, ("a",)),
    ("high-over-edge-of-small-cube", ROW[:1], _held(0, 341, 10, 90), 10.0, WAIT),
    ("high-over-middle-of-cube", ROW[:1], _held(0, 344, 10, 90), 10.0, ("a",)),
    ("high-near-edge-of-wider-cube", [_cube("c", 170, 116, 40)],  # a tower's brick
     Region3D.around((181.9, 100.5, 182.4), (30, 30, 50)), 40.0, ("c",)),
]


@pytest.mark.parametrize("level,held,top,expected", [c[1:] for c in LEVEL_CASES],
                         ids=[c[0] for c in LEVEL_CASES])
def test_supports_of_a_small_held_block(level, held, top, expected):
    assert SearchNode._level(level, held, top) == expected


# Small cubes where the grid leaves only a 2 x 2 (or 1 x 2) bright top face between the
# crease lines; the object-finder asked for more (seeds: the tower of three 12 mm cubes
# written by hand, a 10 mm row).
FINDER_CASES = [  # (id, cube side mm, centres (x, y))
    ("12mm", 12.0, [(-180, 120), (40, 300), (200, 90)]),
    ("10mm", 10.0, [(201, 224), (50, 242), (32, 91), (-244, 358)]),
]


@pytest.mark.parametrize("side,centres", [c[1:] for c in FINDER_CASES],
                         ids=[c[0] for c in FINDER_CASES])
@pytest.mark.parametrize("noise", [2.0, 8.0], ids=["nominal", "4x"])
def test_the_object_finder_sees_every_small_cube(side, centres, noise):
    shapes = {"small": [side] * 3, "crate": [80, 60, 40]}
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise).shoot([block(x, y, (side,) * 3) for x, y in centres]), shapes)
    small = [f.position[:2] for f in found if f.shape == "small"]
    assert len(small) == len(centres) == len(found)
    for x, y in centres:  # each cube found within 3 mm
        assert min(abs(p[0] - x) + abs(p[1] - y) for p in small) < 3.0


# Two 12 x 12 x 110 pillars nearly in line with the side camera: their side silhouettes
# merge and no top face shows there, so the height comes from the silhouette alone
# (objects_columns.Columns.height). Above a pillar everything is dark; a column
# 80 mm too tall, 41 % of it background, won on "dark above it", and its top face's
# footprint, lifted that high, landed 11 mm off (bench seed 1267: the first PICK was
# watched at the wrong place and read as a NO-OP). (back pillar, front pillar) x, y.
PILLARS_IN_LINE = [((209, 215), (201, 85)), ((0, 300), (-5, 120)),
                   ((-150, 250), (-140, 60)), ((100, 320), (110, 150))]


@pytest.mark.parametrize(("back", "front"), PILLARS_IN_LINE)
def test_thin_pillars_in_line_are_found_where_they_stand(back, front):
    shapes = {"pillar": (12, 12, 110)}
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(2.0, seed=5).shoot([block(*back, shapes["pillar"]),
                                 block(*front, shapes["pillar"])]), shapes)
    assert [f.shape for f in found] == ["pillar", "pillar"]
    for x, y in (back, front):  # x, y within 4 mm: where the robot reaches and the
        assert min(math.dist((x, y), f.position[:2]) for f in found) < 4.0  # watch looks
