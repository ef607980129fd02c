"""Layouts no generator had drawn (issue #12), written by hand in tests/recognition/data/.

One row per class of the issue's recognition failures: the scenario, and the cause
that was fixed. Each is watched from its rendered frames and must give the
demonstrated sequence, with every moved object ending on its true supports.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .generated import assert_sequence, assert_supports, assert_targets, watch_file

DATA = Path(__file__).parent / "data"

CASES = {
    # class 4: while the long beam was lifted, the motion-detector's centre (dragged
    # along the beam) lay > 120 mm from the hand; the tracker was re-placed off the hand,
    # lost it, and its first speeds gave a :Far above the spot: an extra PICK of the table
    "class4-long-beam-carried": "cross-beams.yaml",
    # class 4 (lbw bench seed 1054): the person held a 180 mm beam between its ends, fingers
    # 190 mm apart; the tracker sat on one finger, the beam was estimated 100 mm off and its
    # place on the crossing beam was read as on the table (perception/world/wrist.py)
    "class4-beam-taken-across-its-width": "beam-cross-on-bricks.yaml",
    # class 2 (seed 1043, 2x): a slab laid across a row seen from the side covers the row's
    # bright top faces with its own front face: no change in the count of bright pixels,
    # only in their shades (perception/vision/vfd/change.py shade_change)
    "class2-slab-across-a-gap-changes-shades": "slab-across-gap-2x.yaml",
    # class 5 (a user's rearrangement): a plank lifted with a cube on its centre; the
    # search named the cube, and the change-detector did not check that the plank had
    # left too (perception/vision/envnodes/change.py ChangeNode.lifted)
    "class5-plank-picked-with-its-rider": "loaded-plank-centred.yaml",
    # a touch with a block in hand, then the place on the touched block: no :Far, since
    # the hand came back to the same footprint, and no arrival where it had left
    # (perception/vision/envnodes/tracker.py _came_back, search.py leaving)
    "touch-with-a-block-in-hand": "carried-touch.yaml",
    # the same with a crossing beam (bench 1006): the beam still hanging over the spot at
    # the touch's end was read as set down (perception/vision/envnodes/change.py seen_at)
    "beam-touching-its-support": "beam-touching-its-support.yaml",
    # class 2 along y (helper round 4): a brick set down 0 or 2 mm north of another was
    # read as put on it, the :Near search's grown footprint taking the neighbour; the
    # release shows it beside it, at table height (envnodes/placement.py beside_target)
    "row-along-y-touching": "row-y-gap0.yaml",
    "row-along-y-gap-2mm-capped": "row-y-gap2-capped.yaml",
    # class 3 (helper round 4): a 12 mm cube set down behind a tower, hidden from the
    # side; from above, the palm had hidden its spot at the first snapshot
    # (perception/vision/envnodes/change.py unknown_top)
    "small-cube-behind-a-tower": "small-cube-behind-a-tower.yaml",
    # class 6 (bench 1290, 4x): a pick read as 'appeared', which an empty hand cannot do
    # (perception/vision/envnodes/change.py ChangeNode.compare)
    "class6-pick-read-as-place": "pick-read-as-place-4x.yaml",
    # class 6 (bench 1143, 4x): an extra NO-OP after a :Far the tracker's own point gave
    # while a wide-open hand paused (perception/vision/envnodes/tracker.py away)
    "class6-wide-hand-paused": "wide-hand-paused-4x.yaml",
    # class 3 (helper round 5): tops 15 mm apart fell in one support level, so a peg put
    # on a 15 mm cube was read as put across it and the 20 mm cube under it, and a cube
    # on a 15 mm deck over a pier as across deck and pier; a block under another of the
    # level is no co-support (perception/vision/envnodes/search.py confirm)
    "class3-peg-on-a-15mm-cube": "tiny-tower-on-a-15mm-cube.yaml",
    "class3-riders-on-a-15mm-deck": "thin-deck-with-riders.yaml",
    # class 5 (bench rearrange 1213): the hand came down over a knob riding on a slat and
    # lifted the slat; the pick was named after the slat, the motion before it after the
    # knob (lbw_engine/see/actmodel.py _rename)
    "class5-knob-rides-on-the-slat": "knob-rides-on-the-slat.yaml",
    # class 2 (helper round 7, u09 and u21): a step of a staircase put on a row whose
    # cubes are 2 mm apart was read as put on its neighbours too: the :Near search grows
    # the held block by a margin; set down, it shares nothing with them
    # (perception/vision/envnodes/placement.py beside_target)
    "class2-staircase-on-a-row-2mm-apart-x": "staircase-x-gap2.yaml",
    "class2-staircase-on-a-row-2mm-apart-y-noisy": "staircase-y-gap2-noisy.yaml",
    # class 3 (helper round 8, v14): 10 mm cubes laid touching along x; the last one,
    # measured 1.2 mm into its neighbour's footprint, was read as put on it, though it
    # came down to the table, 10 mm under the neighbour's top (placement.py beside_target)
    "class3-tiny-cubes-touching-along-x": "tiny-row-x-touching.yaml",
    # class 6 (helper round 14, v56y, v56u): equal cubes 40 mm apart at pixel 4 / tremor 3;
    # at :Near the hand was 19 mm from the target and 21 mm from its neighbour, and equal
    # tops broke no tie (envnodes/search.py grasped: such a tie waits while the hand is high)
    "class6-equal-cubes-40mm-apart": "equal-cubes-40mm-apart-4x.yaml",
    "class6-five-equal-cubes-40mm-apart": "five-equal-cubes-40mm-apart-4x.yaml",
    # class 5 (helper round 17, u97): a stack of two cubes the size of a listed column was
    # read as the column; a seam across its front face splits it (vfd/objects_stacks.py)
    "class5-two-cubes-the-size-of-a-column": "two-cubes-the-size-of-a-column.yaml",
    # class 5 (generated twins 1154, 2x): the seam hidden behind a column in front; the
    # naming hint counts two cubes, and the images allow them there (vfd/objects_restack.py)
    "class5-cubes-stacked-behind-a-column": "cubes-stacked-behind-a-column-2x.yaml",
    # class 2 (helper round 18, r29): 12 mm pins 1 mm apart along x; the last pin's changed
    # area lay on its neighbour, within FIT_SLACK_MM of the release point, and won
    # (envnodes/placement.py placed_x: a place inside a known block is checked first)
    "class2-pins-1mm-apart-along-x": "pins-1mm-apart-along-x.yaml",
    # class 2 (helper round 18, r58, r82): cubes 1-3 mm apart; the grip of the second one
    # picked was measured at the first one's grasp, 31 mm away and 30 s earlier, as low
    # over its grown footprint; its place on a cube read as on the table
    # (envnodes/hand.py _measure_grip: the hand's last stay over the object)
    "class2-cubes-1mm-apart-stacked-elsewhere": "cubes-1mm-apart-stacked-elsewhere.yaml",
    # class 5 (helper round 18, r70): a lintel taken off its pillars over its middle; the
    # tracked finger, 28 mm off the palm, lay over a pillar, which was named the pick
    # (envnodes/search.py grasped: the palm-checked point chooses)
    "class5-arch-taken-apart-lintel-first": "arch-taken-apart-lintel-first.yaml",
    # class 2 (helper round 17, u62): a 30 mm brick taken from 2 mm behind a row of 40 mm
    # cubes; 150 mm up, the hand was 20 mm from the brick and 24 mm from a cube, and the
    # higher of a near tie was named though neither stood on the other
    # (envnodes/search.py grasped: side by side, a tie waits while the hand is high)
    "class2-brick-behind-a-row-of-taller-cubes": "brick-behind-a-row-of-taller-cubes.yaml",
    # class 3 (helper round 19, r83): a 30 mm cube at the back of the table measured 33 mm
    # and named the listed 35 mm shape; the naming hint's count reads it as the 30
    # (vfd/objects_restack.py _one)
    "class3-heights-30-and-35-at-the-back": "heights-30-and-35-at-the-back.yaml",
    # class 2 (helper round 20): 15 mm cubes 10 mm apart along x; 107 mm up, the slanted
    # approach was 16 mm from its cube and 10 mm from the neighbour, and the neighbour won
    # the tie test (envnodes/search.py grasped: while high, SLANT_MM)
    "class2-small-cubes-close-row-along-x": "small-cubes-close-row-along-x.yaml",
    # class 3 (helper round 20, g3003): a pillar of a 2 x 2 grid touched, judged late with
    # the hand far off; the tops of pillars behind it filled the holder window (a PICK);
    # the top view shows the pillar standing (envnodes/sightings.py left_standing)
    "class3-pillar-touched-in-a-grid": "pillar-touched-in-a-grid.yaml",
}


@pytest.mark.parametrize("name", list(CASES.values()), ids=list(CASES))
def test_unseen_layout_is_recognized(name):
    sc, rec, actions = watch_file(DATA / name)
    assert_sequence(sc, actions)
    assert_supports(sc, rec)
    picked = [op["target"] for op in actions["operations"] if op["operation"] == "PICK"]
    assert picked == [[s.obj] for s in sc.demonstration if s.kind == "pick"]
    placed = [sorted(op["target"]) for op in actions["operations"]
              if op["operation"].startswith("PLACE")]  # each place on its own supports
    assert placed == [sorted(s.on) for s in sc.demonstration if s.kind == "place"]
    assert_targets(sc, actions)


@pytest.mark.parametrize("name", ["pins-1mm-apart-along-x.yaml",
                                  "pins-1mm-apart-along-x-seed11.yaml"])
def test_pins_1mm_apart_are_placed_where_they_landed(name):
    """Helper round 18, r29: the last of four 12 mm pins set down 1 mm apart along x was
    recorded 11 mm off, on the pin beside it: its changed area lay there, 9.5 mm from
    the release point, within FIT_SLACK_MM, so it won unchecked; the plan then put two
    pins in one spot (envnodes/placement.py placed_x checks a place inside a known block
    first). At seed 11 the release point too lay 3.4 mm into the pin beside, measured
    2 mm off: the shallower of the two wins."""
    sc, _, actions = watch_file(DATA / name)
    truth = sc.states[-1].center
    for op in actions["operations"]:
        if op["operation"].startswith("PLACE"):
            name = op["special"][0]
            x = op["final_state"]["positions"][name][0]
            assert abs(x - truth[name][0]) < 5.0, (name, x, truth[name])
