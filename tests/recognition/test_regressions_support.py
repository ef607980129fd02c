"""Generated places whose target (a block or the table) was misread at :Near (`lbw bench`).

Each case is one bench scenario (perception.world.generator) where a PLACE-ON-BLOCK was
read as PLACE-ON-TABLE or the other way round, because of what the guided search
below the held block (Sec. III-E) confirmed against the environment model. Now
the sequence must equal the demonstrator's and every moved object must end on
the objects it really rests on.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .generated import (
    assert_sequence,
    assert_supports,
    assert_targets,
    watch_file,
    watch_generated,
)

DATA = Path(__file__).parent / "data"

CASES = {
    # the tracked hand 35 mm off a held plank's grasp (a finger window clamped at the
    # palm): the loaded plank's centre seemed off the pillar, read as a place on the table
    "seed1064-2x-plank-hand-x": (1064, "2x"),
    # the same error while the fingers opened: the pillar recorded 24 mm from where it
    # was let go, so the plank put on it later seemed to come down beside it
    "seed1028-2x-release-x": (1028, "2x"),
    # a pyramid's upper cube beside the spot grazed the held cube's footprint and hid
    # the two cubes under it (only the topmost level was tried): read as the table
    "seed1031-2x-upper-cube-beside": (1031, "2x"),
    # the jaws closing on the ends of a 160 mm plank drew the motion-detector's point onto
    # one jaw, and the tracker was moved there: the grip was measured 95 mm off the
    # plank's centre, so over its pillar the plank seemed to hang beside it (the fault
    # bench's demonstration gave no plan)
    "fault7007-2x-tracker-onto-a-jaw": (7007, "2x", "classic"),
}


@pytest.mark.parametrize("case", list(CASES.values()), ids=list(CASES))
@pytest.mark.heavy
def test_place_target_recognized(case):
    sc, rec, actions = watch_generated(*case)
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


@pytest.mark.heavy
def test_a_small_cube_over_a_tower_waits_for_the_tower():
    """Bench seed 1157 (small, 2x): a 17 mm cube held 70 mm above a tower of two such
    cubes, its centre not yet over the upper one, made the tower's level wait (it may be
    coming in over it), but the level below answered at once: the cube was recorded on
    the tower's lower cube, and the plan put the upper one where the cube stood. A
    higher level that waits holds back every lower one (SearchNode.near). The same
    scenario's PICK of the third cube, from behind the tower, needs the pick threshold
    scaled to what the side camera sees of it (tests/vision/test_small_blocks.py)."""
    sc, rec, actions = watch_generated(1157, "2x", family="small")
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


def test_an_empty_hand_that_came_to_no_block_gets_an_operation():
    """Generated stacked-start 1266 at 4x (stop 32): the search named the table at an empty
    hand's :Near, so the change-detector had no block region to watch; its comparison gave
    nothing, the local motion matched no Table V row, and analysis stopped on an operation
    of None. Nothing the hand could take or set down was in sight: no change."""
    _, _, actions = watch_generated(1266, "4x", family="stacked-start")
    assert all(op["operation"] is not None for op in actions["operations"]), \
        [op["name"] for op in actions["operations"] if op["operation"] is None]


def test_a_block_set_into_a_tight_grid_is_placed_where_it_fits():
    """Generated gaps 1085 at 2x (stop 32): four cubes in a 2 x 2 grid 7 mm apart. The
    side view's change for a cube set in front of one at its x lay between two columns:
    it was placed 21 mm off, 15 mm into its neighbour, and the robot could not put a
    cube where the plan said (exit 1). A candidate x that goes into a known block loses
    to the hand's release point (placement.placed_x)."""
    sc, rec, actions = watch_generated(1085, "2x", family="gaps")
    assert_sequence(sc, actions)
    final = sc.states[-1]
    for name in ("a-c1", "a-c2", "a-c3", "a-c4"):
        got = rec.env.nodes[name].position
        assert abs(got[0] - final.center[name][0]) < 5 and \
            abs(got[1] - final.center[name][1]) < 5, (name, got, final.center[name])


def test_a_small_cube_let_down_slanting_in_is_put_on_the_one_below():
    """Helper round 15, AM (v65-2high-s1; pixel 4, tremor 3): a 10 mm cube carried to a
    10 mm cube was tracked 9 mm beside it 57 mm up, still slanting in, and that level
    said "beside it" (under DECIDE_MM): the place was read as on the table, 11 mm behind
    the cube. A centre just outside a level waits until the held block is within
    LAND_MM of its top (SearchNode._level)."""
    sc, rec, actions = watch_file(DATA / "small-cube-on-small-cube-held-off-p4t3.yaml")
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


def test_a_small_cube_set_down_beside_a_small_cube_is_put_on_the_table():
    """Helper round 16, BE (p47; pixel 4, tremor 3): a 10 mm cube set down 3 mm beside
    another and slid against it was tracked 7 mm over it 59 mm up, within reach of it,
    and read as put on it. Near the level's edge the verdict waits for the held block
    to come within LAND_MM of its top, in both directions (SearchNode._level)."""
    sc, rec, actions = watch_file(DATA / "small-cube-slid-beside-a-small-cube-p4t3.yaml")
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


def test_a_plate_carried_in_over_two_of_its_four_posts_waits_for_the_others():
    """Stop 35: a 190 x 120 plate put on four posts that stand under its edges by 5 mm
    was carried in 13 mm off its spot, its footprint 18 mm over the two near posts and
    8 mm short of the far ones; that level (the near two) said "beside it", its centre
    42 mm outside them, and the place was read as on the table. A held footprint well
    over some of a level's blocks cannot come down beside them: the level waits
    (SearchNode._level), until the far posts come under it too."""
    sc, rec, actions = watch_file(DATA / "plate-on-posts-under-its-edges.yaml")
    assert_sequence(sc, actions)
    assert_supports(sc, rec)


def test_a_plate_set_down_off_its_legs_keeps_the_legs_the_search_found():
    """Generated stacked-start 1186 (nominal, stop 35): a 120 mm plate on four legs that
    stand under its edges, its set-down point measured 18 mm off. The two legs its
    footprint then missed were dropped from the place, though its centre lay off the
    two it met, where it could not have stood (placement.beside_target): the search's
    four stand, and the plate is put the least distance that sets it on all four
    (placement.onto), as the place's relation and the model's supports then say."""
    sc, rec, actions = watch_generated(1186, "nominal", family="stacked-start")
    assert_sequence(sc, actions)
    assert_targets(sc, actions)
    assert_supports(sc, rec)


@pytest.mark.parametrize("seed,level", [(1148, "2x"), (1032, "4x")])
def test_a_table_top_keeps_the_leg_under_its_far_edge(seed, level):
    """Generated stacked-start 1148 (2x) and 1032 (4x), stop 36: a plate on four legs,
    each 7 mm under its edge. In 1148 the search found all four, and the set-down point,
    measured 5 mm off, met the fourth by 0.8 mm: the plate lies within the measuring
    error of the legs' joint centre, so all four stand (placement._centred). In 1032 the
    search found three; the fourth, as high, centred within their joint footprint and met
    by the plate, is a support too (placement.beside_target, _within)."""
    sc, rec, actions = watch_generated(seed, level, family="stacked-start")
    assert_sequence(sc, actions)
    assert_targets(sc, actions)
    assert_supports(sc, rec)
