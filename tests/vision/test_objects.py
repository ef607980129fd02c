"""Object-finder (Sec. III-B): shapes named and positioned from the two views."""

import numpy as np
import pytest

from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources
from perception.world.scene import Box

from .helpers import CAMS, Film, block

SHAPES = {"brick": [30, 30, 50], "plate": [120, 100, 10], "cube": [40, 40, 40],
          "beam": [100, 20, 20]}


def _layout(name):
    """A named test layout: (shape, Box) pairs."""
    b = {"brick": (30, 30, 50), "plate": (120, 100, 10), "cube": (40, 40, 40),
         "beam": (100, 20, 20)}
    if name == "apart":
        return [("brick", block(-150, 200, b["brick"])), ("brick", block(-100, 320, b["brick"])),
                ("plate", block(150, 220, b["plate"])), ("cube", block(-240, 60, b["cube"])),
                ("beam", block(200, 60, b["beam"]))]
    if name == "corners":
        return [("brick", block(-270, 30, b["brick"])), ("cube", block(270, 370, b["cube"])),
                ("brick", block(270, 30, b["brick"])), ("cube", block(-270, 370, b["cube"]))]
    if name == "tall-behind-low":  # the beam's lifted top face would hit the cube behind it
        return [("beam", block(0, 40, b["beam"])), ("cube", block(0, 140, b["cube"])),
                ("brick", block(10, 300, b["brick"]))]
    if name == "thin-top-hidden":  # the back beam's top face is too thin to see from the side
        return [("beam", block(-162, 153, b["beam"])), ("beam", block(-212, 355, b["beam"])),
                ("beam", block(-234, 252, b["beam"])), ("brick", block(184, 202, b["brick"]))]
    if name == "brick-on-brick":  # the lower top face is hidden: the side view's seam tells
        return [("brick", block(0, 200, b["brick"])), ("brick", block(0, 200, b["brick"], 50))]
    if name == "cube-on-brick":
        return [("brick", block(-150, 300, b["brick"])), ("cube", block(-150, 300, b["cube"], 50)),
                ("plate", block(150, 100, b["plate"]))]
    if name == "stack":  # a brick resting on a plate
        return [("plate", block(100, 200, b["plate"])), ("brick", block(110, 190, b["brick"], 10)),
                ("cube", block(-150, 150, b["cube"]))]
    raise KeyError(name)


def _each_near(found, truth, within):
    """Each true block's nearest reading has its shape and lies within ``within`` mm."""
    for shape, box in truth:
        near = min(found, key=lambda f: np.linalg.norm(np.subtract(f.position, box.center)))
        assert near.shape == shape
        assert np.linalg.norm(np.subtract(near.position, box.center)) < within, (shape, near)


LAYOUTS = ["apart", "corners", "tall-behind-low", "thin-top-hidden", "stack", "brick-on-brick",
           "cube-on-brick"]


@pytest.mark.parametrize("layout", LAYOUTS)
def test_object_finder_names_and_positions_every_block(layout):
    truth = _layout(layout)
    res = VisionResources()
    found = ObjectFinder(CAMS, res).find(Film(seed=4).shoot([b for _, b in truth]), SHAPES)
    assert len(found) == len(truth)
    assert res.in_use == 0  # windows are returned
    for shape, box in truth:
        near = min(found, key=lambda f: np.linalg.norm(np.subtract(f.position, box.center)))
        assert near.shape == shape
        assert np.linalg.norm(np.subtract(near.position, box.center)) < 3.5
        assert np.abs(np.subtract(near.size, box.size)).max() < 4.0


def test_object_finder_on_an_empty_table_finds_nothing():
    det = ObjectFinder(CAMS, VisionResources())
    assert det.find(Film().shoot([]), SHAPES) == []
    assert not det.found()


def _random_layout(seed):
    """Four to six database shapes at random places on the table, at least 25 mm apart."""
    rng = np.random.default_rng(seed)
    placed = []
    while len(placed) < rng.integers(4, 7):
        shape = list(SHAPES)[rng.integers(len(SHAPES))]
        sx, sy, _ = SHAPES[shape]
        x = rng.uniform(-300 + sx / 2, 300 - sx / 2)
        y = rng.uniform(sy / 2, 400 - sy / 2)
        if all(abs(x - b.center[0]) > (sx + b.size[0]) / 2 + 25 or
               abs(y - b.center[1]) > (sy + b.size[1]) / 2 + 25 for _, b in placed):
            placed.append((shape, block(x, y, SHAPES[shape])))
    return placed


@pytest.mark.parametrize("seed", range(6))
def test_object_finder_on_random_layouts(seed):
    truth = _random_layout(seed)
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(seed=seed).shoot([b for _, b in truth]), SHAPES)
    assert sorted(f.shape for f in found) == sorted(s for s, _ in truth)
    _each_near(found, truth, 4.0)


# Issue #12 class 5 (Sec. IX-B3, two objects in contact): a 30x30x60 post standing on a
# 40 mm cube, centred or 3 mm off. Away from the top camera's nadir the post's faces lean
# over the cube's rim: what shows of it is an L, slivers, or nothing, and the cube was
# read as a second post. (x, y) of the cube, then the post's offset on it.
# At (-150, 200) the rim shows as two slivers, front and back, measured as high as the
# column: each was read as a post, and the post's own face taken for their rim.
POST_ON_CUBE = [((200, 300), (0, 0)), ((-250, 50), (0, 0)), ((60, 260), (0, 0)),
                ((0, 340), (3, -2)), ((-250, 40), (3, -2)), ((250, 40), (3, -2)),
                ((-150, 200), (0, 0))]


@pytest.mark.parametrize(("at", "off"), POST_ON_CUBE)
def test_a_post_standing_on_a_cube_is_found_as_two_objects(at, off):
    shapes = {"post": (30, 30, 60), "cube": (40, 40, 40)}
    truth = [("cube", block(*at, shapes["cube"])),
             ("post", block(at[0] + off[0], at[1] + off[1], shapes["post"], 40))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["cube", "post"]
    _each_near(found, truth, 4.0)


# A brick standing across the middle of a 130x40x20 beam cuts the beam's top face in two:
# neither half holds the brick's centre. (x, y) of the beam, whether it lies along x,
# the brick's offset along the beam. Bench seeds 1139 and 1175 (stacked-start, 2x): the
# halves were read as two bricks and the brick as a 70 mm column, so the plan's beam had
# no counterpart in the execution workspace.
BRICK_ACROSS_BEAM = [((-209, 262), True, 0), ((-200, 278), True, 0), ((150, 120), True, 20),
                     ((0, 300), True, -25), ((-180, 200), False, 0), ((200, 330), False, 15)]


def _one_on_a_long_block(long, top, at, along_x, off, noise, seed):
    """A block ``top`` (name, size) standing ``off`` along a longer one ``long`` (name,
    length, width, height) at ``at``: both found once, each within 5 mm."""
    (lname, length, width, height), (tname, tsize) = long, top
    size = (length, width, height) if along_x else (width, length, height)  # axis-aligned
    shapes = {lname: size, tname: tsize}
    on = (at[0] + off, at[1]) if along_x else (at[0], at[1] + off)
    truth = [(lname, block(*at, size)), (tname, block(*on, tsize, height))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=seed).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == sorted((lname, tname)), found
    for shape, box in truth:
        f = next(f for f in found if f.shape == shape)
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 5.0, (shape, f)


@pytest.mark.parametrize(("at", "along_x", "off"), BRICK_ACROSS_BEAM)
def test_a_brick_across_a_beam_is_found_on_one_beam(at, along_x, off):
    _one_on_a_long_block(("beam-t", 130, 40, 20), ("brick", (30, 30, 50)), at, along_x, off,
                         noise=4.0, seed=3)


# A cube near one end of a 110 x 30 x 15 plank leaves a sliver of the plank's face at that
# end, thinner than any top face: it was taken for the cube's own rim and read as a 14 mm
# cube, and the rest of the face as a 71 mm plank (a user's scenario: a loaded plank
# picked up, its rider riding along). (x, y) of the plank, along x, the cube's offset.
RIDER_NEAR_END = [((-150, 100), True, -30), ((150, 250), True, 30), ((0, 330), True, -32),
                  ((-200, 200), False, -30), ((100, 150), False, 30)]


@pytest.mark.parametrize(("at", "along_x", "off"), RIDER_NEAR_END)
def test_a_cube_near_a_planks_end_is_found_on_one_plank(at, along_x, off):
    _one_on_a_long_block(("plank", 110, 30, 15), ("cube", (25, 25, 25)), at, along_x, off,
                         noise=2.0, seed=85)


@pytest.mark.parametrize("along_x", [True, False], ids=["along-x", "along-y"])
def test_blocks_either_side_of_a_taller_one_stay_blocks(along_x):
    """Two cubes touching a brick from both sides show what a cut rim shows from above:
    two faces at one height on either side of a higher one. The side view has no seam
    on the brick's front at the cubes' height, so they stay three blocks on the table."""
    shapes = {"cube": (40, 40, 40), "brick": (30, 30, 50), "beam-t": (110, 40, 40)}
    d = (35.0, 0.0) if along_x else (0.0, 35.0)
    truth = [("brick", block(0, 220, shapes["brick"])),
             ("cube", block(-d[0], 220 - d[1], shapes["cube"])),
             ("cube", block(d[0], 220 + d[1], shapes["cube"]))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=3).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["brick", "cube", "cube"], found
    _each_near(found, truth, 5.0)


# A brick standing on a 50 x 50 x 20 disc (the stacked-start family): the disc's 10 mm ring
# is measured by the side silhouette, as high as the column it frames, and so read as a
# rim. Bench seed 1068 (4x): with the lone-column rule of Columns.height applied
# to it, the ring came out 50 mm high, the disc a 50 mm block and the brick 20 mm on it;
# the robot could not grip the brick beside such a disc. (where, pixel noise)
BRICK_ON_DISC = [((237, 104), 8.0), ((237, 104), 2.0), ((-100, 250), 8.0), ((0, 150), 4.0)]


@pytest.mark.parametrize(("at", "noise"), BRICK_ON_DISC)
def test_a_brick_on_a_disc_is_found_on_the_disc(at, noise):
    shapes = {"brick": (30, 30, 50), "disc": (50, 50, 20), "plate": (100, 120, 10)}
    truth = [("disc", block(*at, shapes["disc"])), ("brick", block(*at, shapes["brick"], 20))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["brick", "disc"], found
    for shape, box in truth:
        f = next(f for f in found if f.shape == shape)
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 5.0, (shape, f)


@pytest.mark.parametrize("noise", [2.0, 4.0], ids=["nominal", "2x"])
def test_a_cube_pushed_to_a_planks_back_edge_is_found(noise):
    """Fault bench 3001 (displace): a cube pushed to the back edge of an inverted T's
    plank overhangs it; its top face is hidden from the side camera, so its height comes
    from the silhouette, and the column under its footprint down to the table is partly
    background (the pillar is narrower). Asking that whole column to be 80 % solid lost
    the cube, and the monitor called it gone. Only the column's top must be solid."""
    shapes = {"cube": (40, 40, 40), "pillar": (50, 50, 50), "plank": (160, 60, 20)}
    edge = block(-50, 365, shapes["cube"], 70)
    scene = [block(-67, 332, shapes["pillar"]), block(-68, 333, shapes["plank"], 50),
             block(-12, 334, shapes["cube"], 70), edge]
    found = ObjectFinder(CAMS, VisionResources()).find(Film(noise=noise, seed=5).shoot(scene),
                                                       shapes)
    near = min(found, key=lambda f: np.linalg.norm(np.subtract(f.position, edge.center)))
    assert near.shape == "cube"
    assert np.linalg.norm(np.subtract(near.position, edge.center)) < 5.0, near


def test_the_top_of_a_three_block_stack_is_found():
    """A 30x30x20 tile on a 40 mm cube on a 50 mm block (the rearrange family, seed 1069):
    the cube's face is a rim of the block and rims the tile; it must not be taken for a
    rim piece, or the tile's face is lost and the first pick is of nothing."""
    shapes = {"tile": (30, 30, 20), "cube": (40, 40, 40), "block": (50, 50, 50)}
    stack = [block(-91, 346, shapes["block"]), block(-91, 346, shapes["cube"], 50),
             block(-91, 346, shapes["tile"], 90)]
    found = ObjectFinder(CAMS, VisionResources()).find(Film(seed=5).shoot(stack), shapes)
    tiles = [f for f in found if f.shape == "tile"]
    assert len(tiles) == 1
    assert np.linalg.norm(np.subtract(tiles[0].position, stack[2].center)) < 4.0


# (where, pixel noise): the rearrange family's stacks (bench seeds 1070 at 2x, 1071 at 4x)
THREE_STACKS = [((-78, 162), 4.0), ((109, 115), 8.0), ((-91, 346), 2.0), ((200, 300), 2.0),
                ((-250, 60), 4.0), ((0, 220), 4.0),
                ((0, 150), 2.0), ((40, 240), 2.0),  # near the top camera's axis: faces split
                ((150, 327), 8.0)]  # 1071 at 4x: a sliver of the block's ring, a column


@pytest.mark.parametrize(("at", "noise"), THREE_STACKS)
def test_every_block_of_a_three_block_stack_is_found(at, noise):
    """A tile on a cube on a block: from above, each ring is 5 mm (2 px) and the creases
    around it leave no face pixel, so the block and the cube read as one 88 mm column.
    The side view's seam and front-face width split it again (``_hidden_stack``, applied
    to its own lower piece); before, the execution could not pick the cube (1070, 1071)."""
    shapes = {"tile": (30, 30, 20), "cube": (40, 40, 40), "block": (50, 50, 50)}
    truth = [("block", block(*at, shapes["block"])), ("cube", block(*at, shapes["cube"], 50)),
             ("tile", block(*at, shapes["tile"], 90))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot([b for _, b in truth]), shapes)
    near = [f for f in found if np.linalg.norm(np.subtract(f.position[:2], at)) < 30.0]
    assert sorted(f.shape for f in near) == ["block", "cube", "tile"]
    for shape, box in truth:
        f = next(f for f in near if f.shape == shape)
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 5.0, (shape, f)


@pytest.mark.parametrize(("at", "noise"), [((-100, 200), 2.0), ((150, 80), 4.0),
                                           ((0, 250), 2.0)])
def test_three_equal_blocks_stacked_are_three(at, noise):
    """A user's three 40x40x30 blocks stacked (helper round 4, s17): the column under the
    top face is 90 mm, the seams show, but the lower piece's front-face width was read
    halfway up it, which for two equal blocks is exactly on their seam's crease: no
    width, no split, and the stack was one object (``_hidden_stack``)."""
    shapes = {"block": (40, 40, 30)}
    truth = [block(*at, shapes["block"], z) for z in (0, 30, 60)]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot(truth), shapes)
    near = sorted((f for f in found if np.linalg.norm(np.subtract(f.position[:2], at)) < 30),
                  key=lambda f: f.position[2])
    assert [f.shape for f in near] == ["block"] * 3
    for f, box in zip(near, truth, strict=True):
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 5.0, f


# The rearrange family's stacks with its whole shape database (a 30x30x50 brick too):
# (bench seed, where, pixel noise, the stack bottom up)
REARRANGE_STACKS = [
    # the rings merge into the block's outline; a cube inside that 5 mm ring paid the ring
    # twice in the fit and lost to "a block on a cube" (seam 10 mm low)
    pytest.param((233, 319), 2.0, ("block", "cube", "tile"), id="1141-teach"),
    pytest.param((54, 249), 4.0, ("block", "cube", "tile"), id="1214-teach"),
    # only the cube's front ring shows: the cover measured 4 mm short of its back edge,
    # which no shape as deep as the cube fitted, so its rim was called a brick
    pytest.param((65, 205), 2.0, ("cube", "brick"), id="1105-execute"),
    # a rim lying inside its cover shows no edge of the lower block: the hidden-ring
    # allowance above must not apply to it, or a tile's face is completed to a block
    pytest.param((182, 326), 4.0, ("block", "cube", "tile"), id="1070-teach"),
    pytest.param((100, 183), 8.0, ("block", "cube", "tile"), id="1071-teach"),
]


@pytest.mark.parametrize(("at", "noise", "stack"), REARRANGE_STACKS)
def test_every_block_of_a_rearrange_stack_is_found(at, noise, stack):
    shapes = {"tile": (30, 30, 20), "cube": (40, 40, 40), "block": (50, 50, 50),
              "brick": (30, 30, 50)}
    truth, z = [], 0.0
    for name in stack:
        truth.append((name, block(*at, shapes[name], z)))
        z += shapes[name][2]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == sorted(stack), found
    for shape, box in truth:
        f = next(f for f in found if f.shape == shape)
        # a middle block's x, y come from the merged rings' face
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 7.0, (shape, f)


def test_two_three_block_stacks_and_a_disc():
    """Bench seed 2033's execute workspace (nominal, rearrange): one stack's merged rings
    came out at 106 mm, under its tile's 110 mm, so they were taken for a block's top
    face, the tile read 5 mm thick, and the robot could not grasp it. A face framing a
    higher one by less than the thinnest shape is a rim (objects_rings.find_rims)."""
    shapes = {"tile": (30, 30, 20), "cube": (40, 40, 40), "block": (50, 50, 50),
              "disc": (50, 50, 20)}
    truth = [("disc", block(46, 70, shapes["disc"]))]
    for at in ((-23, 313), (212, 207)):
        truth += [("block", block(*at, shapes["block"])),
                  ("cube", block(*at, shapes["cube"], 50)),
                  ("tile", block(*at, shapes["tile"], 90))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=2033).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == sorted(s for s, _ in truth)
    # a middle block's x, y come from the merged rings' face: within 6 mm
    _each_near(found, truth, 6.0)


# (bench seed and workspace, where, pixel noise): a tile on a cube on a block whose two
# 5 mm rings each show from above as a face of their own, framing the one above it
SEATED_STACKS = [
    pytest.param((-222, 44), 2.0, id="rearrange-1036-execute"),  # read as block, tile, tile
    pytest.param((-237, 359), 2.0, id="rearrange-1042-execute"),  # every block 5-9 mm off
    pytest.param((216, 180), 4.0, id="rearrange-1007-execute"),  # read as two blocks
    pytest.param((-150, 150), 8.0, id="4x-pixel-noise"),  # the cube 5 mm low
]


@pytest.mark.parametrize(("at", "noise"), SEATED_STACKS)
def test_each_ring_of_a_stack_is_read_at_its_own_seam(at, noise):
    """Neither ring's top face can be seen from the side, so each took the height of the
    tile's face or of the whole column, and its footprint came out too small at that
    height (objects_seams.seat_rims). The robot then grasped the tile 5 mm low, lifted
    the cube with it and set both down together (bench 1042, nominal noise)."""
    shapes = {"tile": (30, 30, 20), "cube": (40, 40, 40), "block": (50, 50, 50),
              "brick": (30, 30, 50)}
    truth = [("block", block(*at, shapes["block"])), ("cube", block(*at, shapes["cube"], 50)),
             ("tile", block(*at, shapes["tile"], 90))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["block", "cube", "tile"], found
    for shape, box in truth:
        f = next(f for f in found if f.shape == shape)
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 2.5, (shape, f)


@pytest.mark.parametrize(("at", "noise"), [((-100, 200), 2.0), ((-150, 300), 2.0),
                                           ((120, 150), 4.0)])
def test_a_stack_of_three_sizes_names_each_block(at, noise):
    """Blocks 50, 40 and 30 mm wide, 30 mm tall, stacked (helper round 4, v17c): the
    rings merge into the big block's outline, which fits an upper block as wide as it
    as well as the middle block inside the ring. The middle block's own front face
    tells (``_hidden_stack``): it was named big, and the robot's unstack had no mid."""
    shapes = {"big": (50, 50, 30), "mid": (40, 40, 30), "small": (30, 30, 30)}
    truth = [(name, block(*at, shapes[name], z))
             for name, z in (("big", 0), ("mid", 30), ("small", 60))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=noise, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["big", "mid", "small"], found
    for shape, box in truth:
        f = next(f for f in found if f.shape == shape)
        assert np.linalg.norm(np.subtract(f.position, box.center)) < 4.0, (shape, f)


def test_a_block_half_off_its_support_stands_on_it():
    """Fault seed 3001 (displace): a cube pushed half off the back edge of an inverted
    arch's plank. Its centre lies past the plank's edge, so its column was read from the
    table up, 110 mm tall, dropped as a ring piece, and the monitor said the cube was
    gone. A face under a quarter of the column's extent on both axes supports it."""
    shapes = {"block": (50, 50, 50), "cube": (40, 40, 40), "plank": (160, 60, 20)}
    truth = [("block", block(-66, 332, shapes["block"])),
             ("plank", block(-68, 333, shapes["plank"], 50)),
             ("cube", block(-13, 334, shapes["cube"], 70)),
             ("cube", block(-51, 365, shapes["cube"], 70))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["block", "cube", "cube", "plank"], found
    _each_near(found, truth, 4.0)


def test_a_plank_between_the_cubes_on_its_ends_holds_up_both():
    """Fault seed 3004 (remove-spare): the inverted arch's pillar was taken away and its
    plank fell flat with a cube still on each end. The plank's top between them was
    read as a rim of one cube's stack, and the other cube, its column then from the
    table up, was dropped: "gone". A rim may support another block as well."""
    shapes = {"block": (50, 50, 50), "cube": (40, 40, 40), "plank": (160, 60, 20),
              "disc": (50, 50, 20)}
    truth = [("plank", block(-162, 239, shapes["plank"])),
             ("cube", block(-234, 238, shapes["cube"], 20)),
             ("cube", block(-111, 239, shapes["cube"], 20)),
             ("disc", block(-237, 351, shapes["disc"])),
             ("block", block(202, 362, shapes["block"]))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == sorted(s for s, _ in truth), found
    _each_near(found, truth, 4.0)


@pytest.mark.parametrize(("low", "wide", "at"), [
    ((40, 40, 40), (90, 80, 20), (-180, 100)),  # helper round 6, e07: two cubes, a slab
    ((30, 30, 45), (110, 100, 12), (200, 80)),  # e04: two legs, a table top
], ids=["cubes-under-a-slab", "legs-under-a-top"])
def test_two_equal_blocks_under_a_wider_one_are_two(low, wide, at):
    """From above only the wide block shows; the side view's seam between the two under it
    is on their own front face, 20 mm behind the wide block's front edge, where the split
    of the lower part looked for it (``_hidden_stack``): one block twice as tall."""
    shapes = {"low": low, "wide": wide}
    truth = [("low", block(*at, low)), ("low", block(*at, low, low[2])),
             ("wide", block(*at, wide, 2 * low[2]))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["low", "low", "wide"], found
    _each_near(found, truth, 6.0)


@pytest.mark.parametrize("at", [(250, 350), (-250, 50), (0, 350), (250, 200), (0, 200)],
                         ids=["back-right", "front-left", "back-middle", "right", "centre"])
def test_three_cubes_on_a_slab_anywhere_on_the_table(at):
    """A 145 mm stack, a slab and three cubes (helper round 6, e08). Away from the top
    camera's nadir, the top cube's face leans outwards and holds the centre of the L the
    cubes leave of the slab's top: the finder took the measured top face for a rim and
    lowered it to a seam, and took the slab's L for the rim right under the top cube. Near
    the corners it found one 85 mm cube; at the centre, all four blocks."""
    shapes = {"slab": (80, 60, 25), "cube": (40, 40, 40)}
    truth = [("slab", block(*at, shapes["slab"]))] + [
        ("cube", block(*at, shapes["cube"], 25 + 40 * k)) for k in range(3)]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=5).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["cube", "cube", "cube", "slab"], found
    for shape, box in truth:  # each block once, where it is
        assert any(f.shape == shape and np.linalg.norm(np.subtract(f.position, box.center)) < 5
                   for f in found), (shape, box.center, found)


@pytest.mark.parametrize("x", [-150, 0, 150])
def test_two_cubes_on_a_slab_in_front_of_the_side_camera(x):
    """A 60 mm slab under two 35 mm cubes at y = 300 (helper round 7, u27): the slab's
    front face read 2 px narrower than its ring's footprint, past the 3 mm the seam
    search allowed, so the ring kept the cubes' height and the middle cube was lost. The
    robot's monitor then saw the cube it had just stacked as gone."""
    shapes = {"slab": (60, 60, 25), "cube": (35, 35, 35)}
    truth = [("slab", block(x, 300, shapes["slab"])), ("cube", block(x, 300, shapes["cube"], 25)),
             ("cube", block(x, 300, shapes["cube"], 60))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(seed=4).shoot([b for _, b in truth]), shapes)
    assert sorted(f.shape for f in found) == ["cube", "cube", "slab"], found
    _each_near(found, truth, 5.0)


@pytest.mark.parametrize(("low", "behind"), [((30, 30, 50), 78), ((40, 40, 40), 70)],
                         ids=["brick-behind-two-bricks", "cube-behind-two-cubes"])
def test_a_block_behind_a_taller_stack_has_its_own_height(low, behind):
    """The side camera cannot see a block standing behind a stack twice its height: its
    top face, lifted to any height that keeps it hidden, lands on the stack's image. It
    was paired with the stack's own top face, 75 mm high, and split into two bricks
    (generated stacked-start 1176), or its column stopped at the stack's top edge, 61 mm
    (1030). It takes the height of the shape its footprint names
    (``objects_hidden.unseen_heights``)."""
    shapes = {"low": low}
    truth = [("low", block(30, 193, low)), ("low", block(30, 193, low, low[2])),
             ("low", block(32, 193 + behind, low))]
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=2.0, seed=5).shoot([b for _, b in truth]), shapes)
    assert len(found) == 3, found
    _each_near(found, truth, 5.0)


COVERED = {"post": (30, 30, 50), "plate": (120, 40, 10), "cube": (30, 30, 30),
           "block": (30, 30, 20), "slab": (50, 50, 15), "cube40": (40, 40, 30)}


@pytest.mark.parametrize("name,truth", [
    # a plate on two posts: from above only the plate (helper round 11, 157)
    ("plate-on-two-posts", [("post", block(-180, 320, COVERED["post"])),
                            ("post", block(-100, 320, COVERED["post"])),
                            ("plate", block(-140, 320, COVERED["plate"], 50))]),
    # a 50 mm slab between two 40 mm cubes (round 11, 44)
    ("slab-between-two-cubes", [("cube40", block(0, 200, COVERED["cube40"])),
                                ("slab", block(0, 200, COVERED["slab"], 30)),
                                ("cube40", block(0, 200, COVERED["cube40"], 45))]),
], ids=lambda v: v if isinstance(v, str) else "")
def test_blocks_the_top_camera_cannot_tell_apart_are_found(name, truth):
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(seed=4).shoot([b for _, b in truth]), COVERED)
    assert len(found) == len(truth), [(f.shape, f.position) for f in found]
    _each_near(found, truth, 8.0)




def _execute_scenario(seed: int, shapes: dict, objects: str) -> str:
    """A scenario whose execution layout is ``objects`` (execute.objects lines); the
    teach side is one block moved once (the finder reads the execution layout only)."""
    first = next(iter(shapes))
    return (f"name: finder\nseed: {seed}\nshapes:\n"
            + "".join(f"  {n}: {list(v)}\n" for n, v in shapes.items())
            + f"teach:\n  objects:\n    t: {{shape: {first}, at: [-200, 100]}}\n"
            "  demonstration:\n    - pick: t\n    - place: t\n      on: table\n"
            "      at: [0, 200]\nexecute:\n  objects:\n" + objects)


def _found_in_world(text: str, settle: bool = True, moved: tuple = ()):
    """The finder's reading of a scenario's execution layout, built in the simulated world
    (settled, then ``moved`` = (name, y) put at y), and the truth: (found, truth, world)."""
    from perception.world.physics import World
    from perception.world.scenario import load_text

    sc = load_text(text, "finder.yaml")
    world = World(sc.execute.objects.values())
    if settle:
        world.settle(0.5)
    for name, y in moved:
        world.y[name] = y
    found = ObjectFinder(CAMS, VisionResources()).find(
        Film(noise=sc.noise.pixel, seed=sc.seed).shoot(world.scene()), sc.shapes)
    truth = [(sc.execute.objects[n].shape, Box("block", c, world.sizes[n]))
             for n, c in world.positions().items()]
    return found, truth, world


INVERTED = {"big": (50, 50, 40), "mid": (40, 40, 30), "small": (30, 30, 25)}


@pytest.mark.parametrize("name,upper", [
    # 30, 40 and 50 mm from the bottom up: the front face's width halfway up the two
    # under the top lay on their seam's crease and read 21 mm (round 13, 07)
    ("widening-three-stack", ["mid", "big"]),
    # two 30 mm cubes under the 50 mm top: a line of the top's own face beyond its
    # crease was read as a second face (round 13, v07b)
    ("top-overhangs-two-cubes", ["small", "big"]),
], ids=lambda v: v if isinstance(v, str) else "")
def test_a_stack_under_an_overhanging_top_is_found(name, upper):
    names = ["s2", *(f"{n}{k}" for k, n in enumerate(upper))]
    found, truth, _ = _found_in_world(_execute_scenario(7, INVERTED, (
        "    s2: {shape: small, at: [150, 200]}\n" + "".join(
            f"    {names[k + 1]}: {{shape: {n}, on: {names[k]}}}\n"
            for k, n in enumerate(upper)))))
    assert sorted(f.shape for f in found) == sorted(["small", *upper]), \
        [(f.shape, f.position, f.size) for f in found]
    _each_near(found, truth, 8.0)


BEHIND_SHAPES = {"cube": (40, 40, 40), "block": (50, 50, 50), "plank": (160, 60, 20)}
BEHIND = """\
    pillar: {shape: block, at: [-66, 332]}
    plank: {shape: plank, at: [-68, 333], on: pillar}
    up: {shape: cube, at: [-21, 333], on: plank}
"""


@pytest.mark.parametrize("x,y", [(-44, 380), (-60, 378)],
                         ids=["fault-bench-3001", "behind-the-pillar"])
def test_a_block_behind_a_structure_is_read_from_above(x, y):
    """A cube knocked off a plank's end onto the table behind the plank's pillar: the
    side view shows it only as a strip of the structure's silhouette, and from above the
    plank hides a band of its top face (fault bench 3001, once a load past its
    support's edge along y tips)."""
    found, truth, _ = _found_in_world(_execute_scenario(
        3001, BEHIND_SHAPES, BEHIND + f"    low: {{shape: cube, at: [{x}, {y}]}}\n"),
        settle=False)
    assert len(found) == len(truth), [(f.shape, f.position, f.size) for f in found]
    _each_near(found, truth, 5.0)


@pytest.mark.parametrize("x,y", [(-200, 300), (200, 300), (-200, 100), (-100, 300)])
def test_a_cube_on_two_equal_discs_is_three_blocks(x, y):
    """The ring around the cube is the upper disc's top, at the seam right under the
    cube; the seam between the discs fits it as well and was taken (round 14, 84: the
    cube read 48 mm tall, one disc lost)."""
    found, truth, _ = _found_in_world(_execute_scenario(
        184, {"cube": (30, 30, 30), "disc": (50, 50, 20)},
        "    x: {shape: cube, at: [200, 100]}\n"
        f"    d1: {{shape: disc, at: [{x}, {y}]}}\n"
        "    d2: {shape: disc, on: d1}\n    y: {shape: cube, on: d2}\n"))
    assert len(found) == len(truth), [(f.shape, f.position, f.size) for f in found]
    _each_near(found, truth, 5.0)


def test_two_shapes_that_fit_a_face_seen_from_above_alone_name_neither():
    """A face read from above alone that two shapes of one height fit (the face short of
    both on the side under the block in front) names neither: the order of the shape
    list chose one (review of stop 31: a 40 x 52 x 40 block listed after the cube)."""
    found, _, _ = _found_in_world(_execute_scenario(
        3001, {**BEHIND_SHAPES, "long": (40, 52, 40)},
        BEHIND + "    low: {shape: cube, at: [-44, 380]}\n"), settle=False)
    assert "long" not in [f.shape for f in found], [(f.shape, f.position) for f in found]


@pytest.mark.parametrize("seed,shapes,objects,moved", [
    # the cube knocked off the plank's end came to rest 3.7 mm past the table's back
    # edge (the loader refuses that place: the world is moved after loading); its face
    # fit the cube without reaching under the plank, and the silhouette's 66 mm won
    (3001, BEHIND_SHAPES, BEHIND + "    low: {shape: cube, at: [-44, 380]}\n",
     ("low", 383.7)),
    # a plate slid off three posts along y lay 2 mm behind them, read 28 mm thick
    # (round 13, v80c)
    (80, {"post": (30, 30, 50), "plate": (160, 60, 10)},
     "    q1: {shape: post, at: [0.5, 199.6]}\n    q2: {shape: post, at: [61.3, 198.9]}\n"
     "    q3: {shape: post, at: [-61.1, 201.2]}\n    pk: {shape: plate, at: [-0.5, 246.7]}\n",
     ("pk", 246.7)),
], ids=["fault-bench-3001-past-the-edge", "plate-behind-three-posts"])
def test_a_block_behind_others_no_stack_explains_is_read_from_above(seed, shapes, objects,
                                                                    moved):
    found, truth, _ = _found_in_world(_execute_scenario(seed, shapes, objects), moved=[moved])
    assert len(found) == len(truth), [(f.shape, f.position, f.size) for f in found]
    _each_near(found, truth, 5.0)
