"""Issue #12 class 1: places beside other blocks, executed by the robot and verified.

Each row is a hand-written scenario (data/NAME.yaml) whose plan (data/NAME.plan.json)
is what perfect detectors would have recognized (``perception.world.oracle``, then
``lbw analyze``), so the rows test execution alone. With jaws that close along x
only, every row failed at instantiation: "the gripper cannot hold ... a jaw would
hit ...". The row says how the places must now be made: which objects the wrist
turns for (jaws along y), which places need the fine motion, and which faces
the demonstration aligned (ALIGN, verified coplanar).
"""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parent / "data"
RULES = load_rules()

# The first of two neighbours goes down with nothing beside it (jaws along x);
# the second has its neighbour 6-14 mm away along x. Blocks of one size along the
# flush axis have both pairs of faces coplanar; the lower face is named.
ROWS = [
    # name, gripped along y, fine motions {object: kind}, aligned (object, with, face)
    ("pyramid-x", {"c1"}, {}, []),  # 6 mm between the bottom cubes along x
    ("align-x", {"b2"}, {"b2": "slide"}, [("b2", "b1", "south")]),  # ALIGN along x
    ("arch-close", {"left"}, {}, []),  # pillars 14 mm apart along x
    ("row-y", set(), {"c1": "slide"}, []),  # in contact along y: set down clear, slid in
    # 12 mm cubes 4 mm apart along y: the 20 mm deep finger grips 4 mm off centre and
    # sticks out on the free side only, so it goes straight down; the top cube rests on both
    ("pyramid-small-y", set(), {}, []),
    # the same square of 16 mm cubes: fingers wider than a cube grip off centre, half
    # the face, clear of the neighbour (jaws.offsets), so two places are held slides;
    # the last is pushed off centre, on the part of its face clear of c2
    ("corner-small", {"c2"}, {"c3": "slide", "c2": "slide", "c4": "push"},
     [("c3", "c1", "west"), ("c2", "c1", "south"), ("c4", "c3", "south")]),
    # the last cube goes into the corner of three: set down clear, pushed in
    ("corner", {"c2"}, {"c2": "slide", "c3": "slide", "c4": "push"},
     [("c3", "c1", "west"), ("c2", "c1", "south"), ("c4", "c3", "south")]),
]


@pytest.mark.parametrize("name,along_y,fine,aligned", ROWS, ids=[r[0] for r in ROWS])
def test_side_contact_places_execute_and_verify(name, along_y, fine, aligned):
    plan = planmod.load(DATA / f"{name}.plan.json")
    result = execute_plan(plan, load(DATA / f"{name}.yaml"), RULES)
    assert result.success, result.message
    ops = [op for op in result.trace.ops if op.focus is not None and op.commands]
    assert {op.focus for op in ops if op.wrist == 90.0} == along_y
    assert {op.focus: op.fine for op in ops if op.fine} == fine
    assert [(a.subject, a.partner, a.face) for a in result.trace.alignments] == aligned
    text = result.commands_text
    assert ("turn-wrist 90.0" in text) == bool(along_y)
    assert text.count("; fine motion") == len(fine)
    assert result.report["expected"]["aligned"] == [
        {"object": s, "with": w, "face": f} for s, w, f in aligned]
