"""Scenarios nobody tuned for (hand-written, or drawn by the bench and pinned), run end to end.

xbridge.yaml (issue #12 class 2): two 40 mm cubes 10 mm apart along x and a slab
across them, narrower than the cubes. Two faults showed on it:
- recognition: after the second place, a false motion point re-placed the
  hand-tracker 70 mm above the fingers; the velocity fitted across that jump
  read as a fast rise (a false :Far), and the slow rest of the depart became a
  REACH and a NO-OP (perception/vision/envnodes/hand.py CONVERGE_FRAMES);
- verification through the cameras: the slab's top, cut in two by the cubes'
  edges, was read as two columns, so the finished structure was not explained
  and the slab was reported gone (objects_faces._top_seen).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from lbw_engine.pipeline.run import run
from perception.world.scenario import load

DATA = Path(__file__).parent / "data"


def _verified(scenario, exact: bool = True, quiet: bool = True):
    """``lbw run`` of ``scenario`` (a name in DATA, or a loaded Scenario): done and verified
    by both verdicts; ``exact``: recognized as demonstrated; ``quiet``: without a
    monitor detection. Returns the run's result."""
    result = run(load(DATA / f"{scenario}.yaml") if isinstance(scenario, str) else scenario)
    if exact:
        assert result.recognition["exact"], result.recognition["difference"]
    assert result.failure is None, result.failure
    report = result.execution.report
    assert report["verification"] == {"cameras": True, "ground_truth": True}
    if quiet:
        assert report["monitor"]["detections"] == []
    return result


def test_slab_across_a_gap_along_x_is_seen_and_done():
    _verified("xbridge")


def test_one_misread_stack_does_not_hide_its_neighbour_from_the_cameras():
    """two-bridges (lbw bench seed 1057): a plank at the back overlaps both towers of the
    other bridge in the side view, so the three are checked as one structure. The first
    tower's top cube is set off by 8 mm; while the whole was refused, the second tower, read
    by the finder as one 80 mm column, lost its top cube and monitoring stopped the run."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules

    plan = planmod.load(DATA / "two-bridges.plan.json")
    result = execute_plan(plan, load(DATA / "two-bridges.yaml"), load_rules())
    assert result.success, result.message
    assert result.report["monitor"]["detections"] == []
    assert result.report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_load_goes_where_its_unmoved_supports_stand_now():
    """plate-on-standing-legs.yaml: the plate was taught across legs the demonstration
    never moved; in the execution layout they stand 100-240 mm east and 100 mm north.
    The plate went to its taught world spot, on one leg (do/placement.py: the load keeps
    its place relative to its supports' taught positions, from the plan's SI)."""
    _verified("plate-on-standing-legs")


def test_an_object_the_plan_never_moves_is_matched_where_it_stands():
    """row-beside-a-standing-cube.yaml: of three equal cubes, the one the demonstration
    left in place must be the execution cube standing at its spot (do/matching.py
    anchors), else the other two are set down beside nothing and the lid falls."""
    result = run(load(DATA / "row-beside-a-standing-cube.yaml"))
    assert result.recognition["exact"], result.recognition["difference"]
    assert result.failure is None, result.failure
    assert result.execution.report["initial_state"]["matching"]["k1"][:2] == \
        pytest.approx([-40, 200], abs=5)


def test_parallel_achieves_run_in_an_order_that_leaves_jaw_room():
    """small-row-middle-last: in the plan's listed order the middle 12 mm cube of a row
    comes last, with 6 mm to each neighbour: no jaw fits either way. Another order of the
    $parallel branches does (do/tracing.py _order)."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules

    plan = planmod.load(DATA / "small-row-middle-last.plan.json")
    result = execute_plan(plan, load(DATA / "small-row-middle-last.yaml"), load_rules())
    assert result.success, result.message
    assert result.report["verification"] == {"cameras": True, "ground_truth": True}


@pytest.mark.parametrize(("name", "blocker", "placing"), [
    ("plate-lying-where-its-legs-go", "pl", "l3"),  # a plan object not yet moved
    ("disk-on-the-goal-spot", "unused-disk-1", "s"),  # an object the plan does not use
])
def test_what_lies_on_a_goal_spot_is_set_aside_first(name, blocker, placing):
    """Helper round 5 (t15, t29): the execution layout has something lying where the
    plan builds, and instantiation stopped: "the spot is occupied". Before the object
    that goes there is picked, what lies on its spot is put on a free one
    (do/setaside.py clear_goal), as blocks resting on a picked one already were."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules

    plan = planmod.load(DATA / f"{name}.plan.json")
    result = execute_plan(plan, load(DATA / f"{name}.yaml"), load_rules())
    assert result.success, result.message
    assert result.report["verification"] == {"cameras": True, "ground_truth": True}
    assert f"'{blocker}' lies where the plan puts '{placing}': set aside" in result.commands_text


@pytest.mark.parametrize(("name", "moved"), [
    # the cube to fetch stands on the cap lying on its goal spot: both are set aside,
    # the cube first, and the cube is then picked where it was put, not where it stood
    ("cap-with-a-cube-on-the-goal-spot", ["r", "c"]),
    # a slab with three cubes on it, taught as a tower elsewhere: every cube above the
    # slab comes off, top first, before the slab is picked (none rides along)
    ("tower-already-standing", ["c1", "c3", "c2"]),
])
def test_stacks_in_the_way_come_down_top_first_and_nothing_is_picked_where_it_was(
        name, moved):
    """Helper round 6 (e05, e08b): both runs were verified only because the monitor noticed
    and repaired what the plan did wrong: a pick at a block's old place after it had been
    set aside itself, and a middle cube set aside with the top one riding on it (riders
    were ordered by the support relations' order, and a block the plan stacks later
    counted as riding now). On a correct plan there is nothing to detect."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules

    plan = planmod.load(DATA / f"{name}.plan.json")
    result = execute_plan(plan, load(DATA / f"{name}.yaml"), load_rules())
    assert result.success, result.message
    assert result.report["monitor"]["detections"] == []
    asides = [line for line in result.commands_text.splitlines() if "set aside at" in line]
    assert [line.split("'")[1] for line in asides] == moved


def test_a_block_lying_under_a_place_is_set_aside_before_it_is_built_over():
    """lbw bench 1271 (beams, 2x): a crossing beam lay on the table between the two legs
    the other beam goes on. Nothing stood in the upper beam's goal box, so it was put
    over the lying one, which no grip could then reach: the robot took the upper beam
    for it and the run ended with a leg "gone" (setaside.trapped)."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules

    plan = planmod.load(DATA / "gen-1271-2x.plan.json")
    result = execute_plan(plan, load(DATA / "gen-1271-2x.yaml"), load_rules())
    assert result.success, result.message
    assert result.report["monitor"]["detections"] == []
    assert "'a-beam2' lies where the plan puts 'a-beam1': set aside" in result.commands_text


def test_a_block_used_only_on_the_way_is_matched_and_used():
    """The base the cube rested on for a while is a plan object, matched to the
    execution layout's base (matching.plan_objects): the ACHIEVE that sets the cube on
    it stopped instantiation ("the relation names 'bs', which is not a plan object")."""
    report = _verified("cube-set-on-a-base-and-taken-off").execution.report
    assert set(report["initial_state"]["matching"]) == {"bs", "tp"}


@pytest.mark.parametrize("name", ["wide-plate-lying-on-the-legs-goals",
                                  "wide-plate-lying-where-its-walls-go"])
def test_a_wide_plate_on_the_goal_spots_is_set_aside(name):
    """A 200 x 130 plate lies where the plan's first blocks go (helper round 11, 109 and
    v109m). It is set aside nearer the build sites when nothing 60 mm clear of them is
    free, and against the table's far edge, past the last row of the spot grid
    (clearing.MARGINS_MM, clearing._steps): the run stopped, 'the spot is occupied'."""
    _verified(name, exact=False)


def test_a_removed_base_is_replaced_before_what_it_carries():
    """The tower's base is removed with the cube on it; a spare base lies aside (helper
    round 11, 58b). The repair puts the spare where the base goes before the cube goes
    on it: redone units keep the plan's order. The cube's unit, redone first, had put it
    on the spare where the spare lay, four times, and the run stopped."""
    report = _verified("tower-base-removed-with-a-spare", exact=False,
                       quiet=False).execution.report
    assert any(d["object"] == "b" for d in report["monitor"]["detections"])
    assert report["monitor"]["repairs"]


def test_a_repair_on_top_of_a_250mm_tower_leaves_the_tower_standing():
    """The gripper waits beside the table at the height it left the tower at: parked at
    150 mm, the repair's reach climbed across the 250 mm tower and its jaws caught the
    top cube; all five fell (helper round 12, v69a; monitor.step_aside)."""
    report = _verified("drop-on-top-of-a-250mm-tower", exact=False, quiet=False).execution.report
    assert {d["object"] for d in report["monitor"]["detections"]} == {"e"}


def test_two_shape_names_of_one_size_are_one_shape():
    """'red' and 'blue' cubes of one size: the finder names every such cube by the first
    name, so an object of either takes it at load (scenario._shapes). Recognition had
    stopped: "the object 'red1' (red) ... is not in the teach workspace"."""
    sc = load(DATA / "two-shape-names-of-one-size.yaml")
    assert {o.shape for o in sc.teach.objects.values()} == {"red"}
    _verified(sc, quiet=False)


def test_a_block_put_on_one_of_a_touching_row_rests_on_that_one_only():
    """Helper round 13, v36c: the cube's learned offset on its support was 1.5 mm towards
    a neighbour the row was built 0.4-1.9 mm from; it came to rest on both, which the
    simulator failed and the cameras passed (do/placement.py ``_off_neighbours``)."""
    _verified("cube-on-the-second-of-two-touching")


def test_a_block_put_on_the_middle_of_a_touching_row_is_aimed_between_its_neighbours():
    """Helper round 13, v36a: the same with a neighbour on either side. The plan keeps
    equal room to both (1.1-1.2 mm each); what the robot then builds is within its
    precision of that: the object-finder reads the cubes it picks a millimetre off, and
    the cube ends with 0.5 mm of its 30 mm footprint over a neighbour's edge, which the
    simulator's verdict counts as a support at more than 0.5 mm (docs/execution.md)."""
    result = run(load(DATA / "cube-on-the-middle-of-three-touching.yaml"))
    assert result.recognition["exact"] and result.failure is None, result.failure
    report = result.execution.report
    assert report["verification"]["cameras"]
    at = report["expected"]["positions"]
    half = 15.0  # the cubes' half width
    left = (at["d"][0] - half) - (at["a"][0] + half)
    right = (at["c"][0] - half) - (at["d"][0] + half)
    assert left > 0.5 and right > 0.5 and abs(left - right) < 0.3, (left, right)


def test_a_block_hemmed_in_on_both_axes_is_freed_by_setting_a_neighbour_aside():
    """Helper round 13, 50: no grip of either post leaves the jaws clear (the other post
    5 mm along x, the lintel 12 mm along y). The lintel can be gripped by its far end:
    it is set aside first, clear of the post's finger room (do/setaside.free_grasp)."""
    result = _verified("posts-hemmed-in-by-a-lintel")
    aside = [note for op in result.execution.trace.ops for note, *_ in op.aside]
    assert any("keeps the jaws off" in note for note in aside), aside


def test_a_small_cube_taken_off_the_top_of_a_column_is_seen_gone():
    """Helper round 15, AH (v54l): a 15 mm cube on a 20 mm cube on a plate on two cubes,
    taken away once placed, with no spare. The finder never separates the small cube;
    the structure posed whole fitted the views within its tolerance (a share of all
    its outlines), and the removal was verified by the cameras (the simulator failed
    it). The 12 side-view pixels only the cube would fill are all dark: it is gone
    (Silhouettes.unshown), and the run ends naming it."""
    result = run(load(DATA / "small-cube-taken-off-a-column-on-a-plate.yaml"))
    assert result.failure == ("execution: 'm' (execute.objects 'rm') (shape t15) is gone "
                              "and the workspace has no spare t15 to replace it")
    assert result.execution.report["verification"] == {"cameras": False, "ground_truth": False}


@pytest.mark.parametrize("scenario", [
    "lintel-on-a-pillar-and-a-static-stack",
    "slab-on-a-pillar-and-a-cube-on-a-static-stack",
    "pillar-set-beside-a-static-stack-and-a-lintel",
    "lintel-on-two-stacks-one-static",
])
def test_a_stack_the_demonstration_never_moved_carries_what_is_built(scenario):
    """Helper round 17 (u199, u91, u198, u90): a stack stands in the teach layout and its
    bottom block is in no operation, so no relation says where that block stood, and
    the stack's top, a support of a lintel, had no taught world position: the lintel
    went to its taught world spot and slid onto one support; a pillar set beside the
    stack went to its own taught spot, 150 mm away; the matcher took the execute
    stack's bottom cube, or a loose one, for the stack's top. Now the top is placed
    from the load it carries (placement.taught_positions), anchors are matched in
    3-D, and the monitor's look poses the unused bottom cube where it was last seen
    (Eyes.others)."""
    _verified(scenario)


def test_a_bridge_on_a_tower_that_stood_from_the_start():
    """Generated bridge 1060 (stop 35): the family now draws, three times in eleven, a
    bridge whose first tower stands in the teach layout and is never moved. The second
    tower went to its taught world spot, 80 mm from the standing one, and the plank fell
    (the standing top counted as carried, since the cube under it is no plan object);
    with that fixed, the matcher gave the standing top's role to a loose cube, and a
    set-aside put the plank on the second tower's spot, kept beside the standing one."""
    from perception.world.generator import generate

    _verified(generate(1060, "nominal", family="bridge").scenario())


def test_a_repair_starts_from_beside_the_table():
    """A tower's middle block is taken away once built and the cap falls onto the base
    (helper round 19, r54). The repair first sets the cap aside; the model it was traced
    in had the gripper at home, over the cap, so its reach was skipped as a null move and
    the jaws came down slanted from beside the table, knocking the cap onto its side
    (exit 1, 'lies on its side'). The gripper waits beside the table after every unit,
    and the repair's model now says so: its first fetch begins with a reach."""
    result = _verified("tower-middle-removed-cap-fallen", exact=False, quiet=False)
    report = result.execution.report
    assert {d["object"] for d in report["monitor"]["detections"]} >= {"b"}
    assert report["monitor"]["repairs"]


def test_an_unused_block_slid_onto_a_goal_is_set_aside_first():
    """An unused post is slid onto the cube's goal spot after the first unit (helper round
    19, r77). Nothing the plan uses was off, so nothing was re-traced, and the cube was
    set down on the post. A pending unit's goal taken by an unused object is a detection
    ('in the way'); the re-trace sets the post aside before the cube goes there."""
    report = _verified("unused-post-slid-onto-a-goal", exact=False, quiet=False).execution.report
    assert [d["kind"] for d in report["monitor"]["detections"]] == ["in the way"]
    assert report["robot"]["grasps"] == ["b2", "x", "a2"]  # the post, then the cube
