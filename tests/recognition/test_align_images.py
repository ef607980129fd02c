"""ALIGN recognized from the images (Sec. V-B5, Table V: FineMotion with CoplDet positive).

At the :Split of place-and-align's second place the palm and the fingers still
hide the edges the coplanar-detector looks for; the FineMotion ends there but its
classification waits until the hand has cleared the faces (or the LocalMotion
ends), using only frames up to the one it is decided on.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .generated import assert_sequence, watch_file

SCENARIO = "place-and-align"
DATA = Path(__file__).parent / "data"


def _fine_names(op: dict) -> list[str]:
    """Operation names of a top-level operation's fine motions."""
    return [f["operation"] for f in op.get("fine", [])]


def test_place_and_align_fine_ops_contain_align(watched):
    w = watched(SCENARIO)
    ops = w.actions["operations"]
    assert len(ops) == len(w.truth)
    for op, truth in zip(ops, w.truth, strict=True):
        expected = "ALIGN" in [f.operation for f in truth.fine]
        assert ("ALIGN" in _fine_names(op)) == expected, (op["name"], _fine_names(op))
    assert any("ALIGN" in _fine_names(op) for op in ops)


def test_align_names_the_block_it_lines_up_with(watched):
    w = watched(SCENARIO)
    place = next(op for op in w.actions["operations"] if "ALIGN" in _fine_names(op))
    relations = place["final_state"]["relations"]
    assert ["coplanar", "block2", "block1"] in relations


def test_a_block_set_down_flush_without_a_slide_is_no_align():
    """ALIGN is a slide (Sec. V-B5): cubes put down in line at their own positions are
    placed, not aligned, though their west faces end coplanar (CoplanarNode.compare)."""
    sc, _, actions = watch_file(DATA / "row-flush-y.yaml")
    assert_sequence(sc, actions)
    fine = [f["operation"] for op in actions["operations"] if op["special"]
            for f in op["fine"]]
    assert fine == ["NO-OP"] * 3


def test_a_block_put_down_behind_a_tall_pillar_is_no_align():
    """Helper round 12, 14: a 150 mm pillar in front hid a finger of the hand placing a
    grid's cube behind it; the tracked hand moved 8 mm while the palm seen from above
    stayed put, and the place read as an ALIGN (CoplanarNode.compare, TOP_SHARE)."""
    sc, _, actions = watch_file(DATA / "grid-behind-a-150mm-pillar.yaml")
    assert_sequence(sc, actions)
    fine = [f["operation"] for op in actions["operations"] if op["special"]
            for f in op["fine"]]
    assert "ALIGN" not in fine


def test_a_block_set_on_one_of_its_own_size_is_no_align():
    """Side faces line up with a neighbour's only at one level: a 10 mm cube set exactly
    on another has its bottom 10 mm above the other's, and was read as ALIGNed with it
    (helper round 9, w23; CoplanarNode.status, LEVEL_SHARE). A place whose target waits
    for the held cube to come down near the lower one's top (SearchNode._level, LAND_MM)
    is decided only then (its start dated back), and a slow motion before the decision is
    not watched as a fine motion of it: not every place here shows one."""
    sc, _, actions = watch_file(DATA / "tower-of-10mm-cubes.yaml")
    assert_sequence(sc, actions)
    fine = [f["operation"] for op in actions["operations"] if op["special"]
            for f in op["fine"]]
    assert fine and set(fine) == {"NO-OP"}


@pytest.mark.parametrize("name,aligns", [
    # an 8 mm slide, the faces hidden at its start (CoplanarNode.compare)
    ("align-short-slide.yaml", [["NO-OP"], ["ALIGN"]]),
    # a slid block measured 5.5 mm into its neighbour at the release (OVERLAP_MM)
    ("align-south-then-east.yaml", [["NO-OP"], ["ALIGN"], ["ALIGN"]]),
    # y-jaws at the table's end: x from the stereo palm, the level from the target
    # (HandTracker._one_band, coplanar.settled)
    ("align-across-the-camera.yaml", [["ALIGN"]]),
    # the fingertips hidden by a block in front while the hand comes down
    # (HandTracker._unhidden)
    ("align-behind-a-block.yaml", [["ALIGN"]]),
    # a palm-to-fingertip drop learned too long, never corrected (HandTracker._edge_below)
    ("align-on-two-faces.yaml", [["NO-OP"], ["ALIGN"], ["ALIGN"]]),
    # a 30 x 60 block slid 7 mm: its boxes measured 4.6 then 2.2 mm from flush (_closed)
    ("align-a-long-block-west-7mm.yaml", [["NO-OP"], ["ALIGN"]]),
    # set down flush on the named face, slid 6 mm into contact: coplanar at both ends
    ("align-flush-then-slid-into-contact.yaml", [["NO-OP"], ["ALIGN"]]),
    # slid along a 120 mm tower in front, which hides the fingers from the side camera:
    # x, y from the top view's palm (CoplanarNode._from_above)
    ("align-behind-a-120mm-tower.yaml", [["NO-OP"], ["ALIGN"]]),
    # slid into line with a 120 mm tower's north face, measured 7 mm from it (CONTACT_MM)
    ("align-north-beside-a-120mm-tower.yaml", [["NO-OP"], ["ALIGN"]]),
], ids=["8mm-slide", "measured-into-its-neighbour", "jaws-across-the-camera",
        "behind-a-block", "two-faces-of-one-block", "long-block-7mm", "flush-then-into-contact",
        "behind-a-tall-tower", "beside-a-tall-tower"])
def test_a_slide_into_line_is_an_align(name, aligns):
    sc, _, actions = watch_file(DATA / name)
    assert_sequence(sc, actions)
    fine = [[f["operation"] for f in op["fine"]] for op in actions["operations"]
            if op["special"] and op["fine"]]
    assert fine == aligns
