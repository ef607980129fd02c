"""The robot watches itself (issue #13): faults are detected, repaired and verified by the cameras.

One run per fault kind (design.md ``execute.faults``), each with a hand-written
plan of tests/data, and a fault that cannot be repaired (exit 1, the object
named). The robot is never told about a fault: the injector acts on the world.
"""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.paths import bundled_scenario

DATA = Path(__file__).resolve().parent.parent / "data"


def scenario(tmp_path, name, faults, extra=""):
    """The bundled scenario ``name`` with faults (and extra execution objects: the bundled
    scenarios end with their execute.objects)."""
    text = bundled_scenario(name).read_text().rstrip("\n") + "\n" + extra
    path = tmp_path / f"{name}-faults.yaml"
    path.write_text(text + "  faults:\n" + "".join(f"    - {f}\n" for f in faults))
    return path


def execute(tmp_path, name, path, capsys, plans=DATA):
    """``lbw execute`` of plan ``name`` (in ``plans``) on scenario ``path``: the exit code,
    execution.json and stderr."""
    out = tmp_path / "out"
    code = main(["execute", str(plans / f"{name}.plan.json"), str(path), "--out", str(out)])
    err = capsys.readouterr().err
    return code, json.loads((out / "execution.json").read_text()), err


CASES = [
    # a brick let go halfway through its transfer lands on the table
    pytest.param("unstack", ["{during: 1, kind: drop}"], "", "drop", ["achieve01"],
                 id="drop"),
    # the tower's base slid away after the first cube was put on it: the cube falls
    # onto the base's spot, is set aside, the base goes back and the cube on it
    pytest.param("tower", ["{after: 2, kind: displace, object: s1, by: [-60, 40]}"], "",
                 "displace", ["achieve02", "achieve01", "achieve02"], id="displace-support"),
    # a cube taken away after it was stacked: a spare cube replaces it
    pytest.param("tower", ["{after: 3, kind: remove, object: k2}"],
                 "    k5: {shape: cube, at: [100, 60]}\n", "remove", ["achieve03"],
                 id="remove-with-spare"),
]


@pytest.mark.parametrize("name,faults,extra,kind,repaired", CASES)
def test_fault_is_detected_repaired_and_verified(tmp_path, capsys, name, faults, extra, kind,
                                                 repaired):
    path = scenario(tmp_path, name, faults, extra)
    code, report, err = execute(tmp_path, name, path, capsys)
    assert code == 0, err
    assert [f["kind"] for f in report["faults"]] == [kind]
    detections = report["monitor"]["detections"]
    assert detections and all(d["t"] >= report["faults"][0]["t"] for d in detections)
    assert {"operator", "object", "expected", "observed", "t"} <= set(detections[0])
    assert [r["operator"] for r in report["monitor"]["repairs"]] == repaired
    assert all(r["commands"] > 0 for r in report["monitor"]["repairs"])
    assert report["verification"] == {"cameras": True, "ground_truth": True}
    assert report["success"] is True and report["failure"] is None


def test_an_aligned_block_pushed_off_its_partners_face_is_redone():
    """After each ACHIEVE the faces aligned so far are checked as the final verdict checks
    them: a 4 mm push is within the 5 mm position tolerance but not the 2 mm coplanar one
    (pipeline/monitor.py); it was found only at the end, with no repair left to make."""
    from lbw_engine.pipeline.run import run
    from perception.world.scenario import load

    result = run(load(Path(__file__).parent / "data" / "aligned-block-pushed-4mm.yaml"))
    report = result.execution.report
    assert [d["kind"] for d in report["monitor"]["detections"]] == ["aligned"]
    assert [r["operator"] for r in report["monitor"]["repairs"]] == ["achieve02"]
    assert report["verification"] == {"cameras": True, "ground_truth": True}
    assert result.failure is None, result.failure


def test_a_drop_beside_a_standing_block_is_repaired(tmp_path, capsys):
    """A drop is a slip (perception/world/faults.py SLIP_MM): the jaws flung fully open
    came down around the place spot 150 mm wide and toppled the leg standing beside it."""
    code, report, err = execute(tmp_path, "table-legs", DATA / "table-legs-drop.yaml", capsys)
    assert code == 0, err
    assert [f["kind"] for f in report["faults"]] == ["drop"]
    assert [r["operator"] for r in report["monitor"]["repairs"]] == ["achieve01"]
    assert report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_repair_turns_the_wrist_from_where_the_last_unit_left_it(tmp_path, capsys):
    """The repair's commands start from the measured state and the wrist as it is: a
    block gripped across y, displaced, is gripped across x again after a turn (the
    model of the measured state had the wrist straight and skipped it: helper round 9)."""
    code, report, err = execute(tmp_path, "narrow-block-displaced",
                                DATA / "narrow-block-displaced.yaml", capsys)
    assert code == 0, err
    assert [d["kind"] for d in report["monitor"]["detections"]] == ["position"]
    assert report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_fault_that_never_fires_is_reported(tmp_path, capsys):
    """A drop tied to an ACHIEVE the plan never reaches changes nothing; the user is told
    (execution.json faults_not_injected, a note on stderr), not left to believe it was tried."""
    path = scenario(tmp_path, "unstack", ["{during: 5, kind: drop}"])
    code, report, err = execute(tmp_path, "unstack", path, capsys)
    assert code == 0
    assert report["faults"] == []
    missed = report["faults_not_injected"]
    assert [(f["kind"], f["during"]) for f in missed] == [("drop", 5)]
    assert isinstance(missed[0]["line"], int)
    assert "note: the drop during ACHIEVE 5" in err and "never happened" in err


def test_a_removed_object_without_a_spare_ends_the_run_naming_it(tmp_path, capsys):
    path = scenario(tmp_path, "unstack", ["{after: 1, kind: remove, object: t}"])
    code, report, err = execute(tmp_path, "unstack", path, capsys)
    assert code == 1
    assert report["success"] is False
    # the plan's name, and the one the scenario's author gave the block removed
    assert report["failure"] == ("execution: 'top1' (execute.objects 't') (shape brick) is "
                                 "gone and the workspace has no spare brick to replace it")
    assert [d["object"] for d in report["monitor"]["detections"]] == ["top1"]
    assert report["monitor"]["repairs"] == []
    assert "top1" in err
    # both verdicts on what stands when the run stopped: the structure is unfinished
    assert report["verification"] == {"cameras": False, "ground_truth": False}
    # the commands run before the stop stay in commands.txt, the reason last
    commands = (tmp_path / "out" / "commands.txt").read_text().splitlines()
    assert " close-hand" in commands and " open-hand 42.0" in commands
    assert commands[-1].startswith(";;; stopped: 'top1'")


EXEC_DATA = Path(__file__).resolve().parent / "data"


@pytest.mark.parametrize("fault,code,seen", [
    # the post slid out from under the beam's end: the beam tips off the other post,
    # and both go back (before balance.py the beam hung level on one post)
    ("{after: 3, kind: displace, object: q2, by: [70, 0]}", 0, "b"),
    # the post taken away: the beam falls, and with no spare post the run stops naming it
    # (before, the beam hung on one post, hiding the post's absence from both cameras,
    # and the cameras' verdict was true and the simulator's false)
    ("{after: 3, kind: remove, object: q2}", 1, "q"),
], ids=["displace", "remove"])
def test_a_beam_along_y_loses_a_post(tmp_path, capsys, fault, code, seen):
    text = (EXEC_DATA / "arch-along-y.yaml").read_text().rstrip("\n")
    path = tmp_path / "arch-along-y.yaml"
    path.write_text(text + f"\n  faults:\n    - {fault}\n")
    got, report, err = execute(tmp_path, "arch-along-y", path, capsys, plans=EXEC_DATA)
    assert got == code, err
    assert seen in {d["object"] for d in report["monitor"]["detections"]}
    assert report["verification"]["cameras"] == report["verification"]["ground_truth"]
    if code:
        assert report["failure"].startswith("execution: 'q' (execute.objects 'q2')")


def test_no_detection_without_faults(tmp_path, capsys):
    code, report, err = execute(tmp_path, "unstack", bundled_scenario("unstack"), capsys)
    assert code == 0, err
    assert report["monitor"]["detections"] == [] and report["monitor"]["repairs"] == []
    assert [u["operator"] for u in report["monitor"]["units"]] == ["achieve01"]
    assert report["faults"] == []
    assert report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_place_the_watch_did_not_see_is_redone_once(tmp_path, capsys, monkeypatch):
    """A drop can land within the cameras' tolerance of the goal (fault bench seed 3000:
    a table top, 5.1 mm off, passed the look). The watch, which saw no place, is the
    evidence: the unit is redone. A second miss on the same object is the recognizer's
    (a watch that sees nothing here), so it is redone once, not until the repairs run out."""
    from lbw_engine.pipeline.robotwatch import RobotWatch

    monkeypatch.setattr(RobotWatch, "end", lambda self: [])
    code, report, err = execute(tmp_path, "tower", bundled_scenario("tower"), capsys)
    assert code == 0, err
    units = sorted({u["operator"] for u in report["monitor"]["units"]})
    assert sorted(r["operator"] for r in report["monitor"]["repairs"]) == units
    missed = [d for d in report["monitor"]["detections"] if d["kind"] == "operation"]
    assert missed and all(d["observed"] is None for d in missed)
    assert report["verification"] == {"cameras": True, "ground_truth": True}


HIDDEN = Path(__file__).resolve().parent / "data"


@pytest.mark.parametrize("name,units", [
    # an arch: the two pillars under the beam are hidden from the top camera
    ("gen-1037-2x", ["achieve02", "achieve01", "achieve03"]),
    # a plate on three bricks: the bricks are hidden from the top camera
    ("gen-1024-nominal", ["achieve03", "achieve02", "achieve01", "achieve04"]),
])
def test_no_detection_when_supports_end_hidden(tmp_path, capsys, name, units):
    """Layouts where the finished structure's outlines fall between pixels: the expected
    poses must still be accepted (a sub-pixel offset flips whole rows of long edges)."""
    code, report, err = execute(tmp_path, name, HIDDEN / f"{name}.yaml", capsys, HIDDEN)
    assert code == 0, err
    assert report["monitor"]["detections"] == [] and report["monitor"]["repairs"] == []
    assert [u["operator"] for u in report["monitor"]["units"]] == units
    assert report["verification"] == {"cameras": True, "ground_truth": True}


@pytest.mark.parametrize("name", ["slab-robot-lowers-fast.yaml", "unstack-equal-blocks.yaml",
                                  "disk-on-the-lintel.yaml", "l-shape-mixed.yaml",
                                  "tower-behind-a-tall-post.yaml",
                                  "narrow-block-touching-a-cube.yaml", "cube-moved-twice.yaml",
                                  "l-of-cubes-pushed-into-contact.yaml",
                                  "tower-goal-against-a-cube.yaml",
                                  "set-aside-in-front-of-a-taller-block.yaml",
                                  "grid-2x2-touching.yaml",
                                  "grid-2x2-touching-corner-last.yaml",
                                  "pillar-on-a-150mm-pillar.yaml",
                                  "cube-10mm-6mm-behind-a-60mm-block.yaml",
                                  "cube-10mm-30mm-behind-a-60mm-block.yaml",
                                  "cube-10mm-6mm-beside-a-60mm-block.yaml",
                                  "cube-set-aside-beside-a-capped-post.yaml",
                                  "cube-10mm-25mm-in-front-of-an-80mm-post.yaml",
                                  # its pick seen by the front face's shade (round 12, 27)
                                  pytest.param(
                                      "cube-10mm-starting-on-a-60mm-block.yaml",
                                      marks=pytest.mark.xfail(strict=True, reason=(
                                          "the object-finder misses the 60 mm block "
                                          "under the 10 mm cube and reads the cube on "
                                          "the table; this passed only while the "
                                          "kinematic jaws crushed the block through "
                                          "the table (stop 39: the arm's force "
                                          "limit)"))),
                                  "cube-10mm-6mm-in-front-of-a-60mm-block.yaml",
                                  "cube-carrying-a-block-as-wide.yaml"],
                         ids=["robot-lowers-fast", "equal-blocks-stacked", "disk-set-aside",
                              "withdraw-beside-a-block", "post-the-plan-leaves-alone",
                              "pick-beside-a-touching-block", "picked-where-just-put",
                              "pushed-into-contact", "picked-against-a-goal",
                              "picked-before-a-taller-block", "pushed-into-a-corner",
                              "pushed-into-a-corner-last", "stepped-aside-from-a-tall-tower",
                              "small-pick-hidden-behind-a-block", "small-cube-behind-a-block",
                              "small-pick-beside-a-tall-block", "set-aside-under-no-overhang",
                              "small-cube-before-a-post", "small-cube-starting-on-a-block",
                              "small-cube-before-a-block", "carry-a-rider-as-wide"])
def test_no_detection_on_a_clean_run_of_a_users_scenario(name):
    """Fault-free runs of users' scenarios (helper round 4): the monitor must not see a
    difference and redo an ACHIEVE (search.py leaving; matching.py _covered). Helper
    round 7 (u43): the robot's pick of a 10 mm disk set aside off the lintel showed 0.39
    of the holder window, where a pick asked 0.6; the monitor took the lintel's pick for
    the disk's and set the lintel down again (change.py, a held block's fill). Round 7
    (u17): counting a pick's shade change read the robot's withdraw from a block set down
    5 mm from another as a second PICK (that rule was taken out again). Round 8 (v06):
    the robot watch did not know the 150 mm post the plan leaves alone, whose image
    covered a cube's spot far behind it, and read the cube's pick as a NO-OP. Round 10
    (y06, v06c): a cube pushed into the corner of a 2x2 grid touching was let go flush
    with the neighbour across the push; 1 mm off, it sat on that one's edge, fell off,
    and the closed jaws came down on it (fine.py, _clear_across). Round 11 (v110n): the
    gripper went straight down to the look pose from the top of a 270 mm tower and
    caught it (monitor.step_aside). Round 11 (v53a, v53g, v53h): a 10 mm cube beside or
    behind a 60 mm block was read 51 mm tall by the finder (objects_hidden), its pick
    named the block (search.confirm) or, still behind it, was judged before the hand
    rose into view (ChangeNode.too_small). Round 11 (32): a cube set aside 2 mm under a
    plate's overhang was hidden from above (clearing._clear keeps the column free).
    Round 12 (v26b) and round 11 (v53b): a 10 mm cube in front of a taller block was
    read 82-100 mm tall (objects_hidden._in_front_of). Round 14 (v48y): the robot's jaws
    held the block riding on the cube it picked (World.between)."""
    from lbw_engine.pipeline.run import run
    from perception.world.scenario import load

    result = run(load(Path(__file__).parent / "data" / name))
    assert result.failure is None, result.failure
    report = result.execution.report
    assert report["monitor"]["detections"] == [] and report["monitor"]["repairs"] == []
    assert report["verification"] == {"cameras": True, "ground_truth": True}


def test_a_block_tipped_onto_its_side_ends_the_run_naming_it(tmp_path, capsys):
    """Helper round 5 (t35): a 20 x 70 x 30 block knocked onto its side is seen 31 x 68 x
    19 from the cameras, each extent off by less than TOPPLED_MM, so the robot kept
    setting it down on its side and ended saying another block was gone. On the table
    its height is reliable, and lying fits it far better than upright. (The block is
    tipped off its base by a displace: in t35 it was knocked over by the empty jaws
    coming down on a dropped block, which the arm's force limit now stops.)"""
    name = "oblong-tipped-off-its-base"
    code, report, err = execute(tmp_path, name, DATA / f"{name}.yaml", capsys)
    assert code == 1, err
    assert report["failure"].startswith("execution: 'o2' (execute.objects 'p1') lies on its "
                                        "side")
    assert "cannot stand it up" in report["failure"]
    assert report["ground_truth_toppled"]  # the simulator agrees it fell


@pytest.mark.parametrize("name", ["tiny-row-y-gap6", "small-row-13mm", "tiny-row-x-gap6",
                                  "tiny-row-y-gap4", "tiny-tower-10mm"])
def test_a_small_block_set_down_by_the_robot_is_seen_placed(tmp_path, capsys, name):
    """Helper round 5 (t10): 16 mm cubes in a row along y. The robot lowers a block slowly,
    so the landing box already shows it at the first snapshot, and the holder window
    held 0.2 of block pixels where HOLDING asks 0.6: the place was missed, two false
    detections followed and the cube was picked and placed again. A held block shows
    in the window as much as its size lets it (HandState.held_fill). lbw bench seed 1012
    (nominal, 13 mm cubes in a row along y): 0.12 of the window, four detections. Helper
    round 7 (u24): along x the jaws close across y, and a finger hides the cube from the
    side, from start to release: nothing between the fingers, and nothing seen to appear
    where the hand had been (change.py ``revealed``). Helper round 9: a 10 mm cube
    set on another (w83) and a 12 mm one set 4 mm in front of another (w24) fill 0.06
    of the window, as an empty hand does; the first is seen by its crease lines where
    it was let go (``seen_at`` with creases), the second from above once the gripper
    has left the spot (``palm_over``: the motion waits)."""
    code, report, err = execute(tmp_path, name, DATA / f"{name}.yaml", capsys)
    assert code == 0, err
    assert report["monitor"]["detections"] == [] and report["monitor"]["repairs"] == []
    assert all(op["agree"] for op in report["monitor"]["operations"])


@pytest.mark.parametrize(("position", "size", "want", "tipped"), [
    ((0, 200, 9.6), (31, 68, 19), (20, 70, 30), True),  # t35: on its side
    ((0, 200, 15.2), (22, 70, 30.5), (20, 70, 30), False),  # upright, measured a bit off
    ((0, 200, 20), (40, 40, 40), (40, 40, 40), False),  # a cube has no other axis up
    ((0, 200, 20.5), (41, 39, 41), (40, 40, 40), False),  # ... whatever the noise
    ((0, 200, 15.0), (40, 40, 30), (40, 40, 40), False),  # ... or its height read
    ((0, 200, 49.6), (31, 68, 19), (20, 70, 30), False),  # not on the table: heights weak
    # round 15, AL: a plank read 42 x 30 x 46 (columns merged) fits lying a little less
    # badly than upright, and fits neither
    ((0, 200, 23.0), (42, 30, 46), (160, 30, 15), False),
], ids=["oblong-on-its-side", "oblong-upright", "cube", "cube-noisy", "cube-read-low",
        "off-the-table", "a-misreading-fits-no-orientation"])
def test_which_blocks_on_the_table_have_tipped(position, size, want, tipped):
    """fallen.tipped: fault bench 5004, 5007, 7005 and 7008 crashed on a cube, whose
    shape has no other axis that could be up (an empty min)."""
    from lbw_engine.do.fallen import tipped as reads_tipped

    assert reads_tipped(position, size, want) is tipped


@pytest.mark.parametrize(("size", "want", "tilted"), [
    ((139, 32, 80), (160, 30, 15), True),  # a plank leaning on a pillar (round 15, 44)
    ((56, 40, 56), (40, 40, 40), True),  # a cube turned 45 degrees
    ((40, 40, 40), (40, 40, 40), False),  # upright
    ((45, 40, 47), (40, 40, 40), False),  # upright, read 5-7 mm large (review)
    ((35, 30, 35), (30, 30, 30), False),  # ... 5 mm
    ((66, 30, 52), (60, 30, 40), False),  # a brick read 12 mm tall
    ((22, 70, 30.5), (20, 70, 30), False),  # upright, measured a bit off
    ((85, 30, 46), (30, 30, 30), False),  # round 15, 55: a cube merged with its neighbour
    ((39, 24, 42), (40, 40, 40), False),  # fault bench 9001: a cube misread
    ((21, 21, 31), (20, 60, 20), False),  # round 15, 5e: a 20 x 60 brick misread
    ((42, 30, 46), (160, 30, 15), False),  # round 15, 55: a plank's columns merged
], ids=["plank-leaning", "cube-45", "cube-upright", "cube-read-large", "small-cube-read-large",
        "brick-read-tall", "oblong-upright", "cube-merged", "cube-misread", "brick-misread",
        "plank-merged"])
def test_which_readings_are_a_block_turned_over(size, want, tilted):
    """monitor._upright stops a run for a block that fell over: its extents must be its
    shape's turned part way in the x-z plane or in another order (a block on its side on
    the table is also ``_tipped``'s), not any other footprint (round 15, AL: a misread
    cube was said to lie on its side and a repairable run ended)."""
    from lbw_engine.do.fallen import on_side
    from lbw_engine.do.fallen import tilted as reads_tilted

    assert (reads_tilted(size, want) or on_side(size, want)) is tilted


# (bench seed, level, family, detections at most, what the robot watch missed)
QUIET_RUNS = [
    (1192, "nominal", "small", 0, "a 19 mm cube set down at the table's corner, tracked 4 mm "
     "low: its bottom below the table top left the search no region, so no arrival"),
    (1264, "nominal", "small", 0, "a 10 mm cube picked behind a crate: hidden from the "
     "side, 0.04 of the holder window, the palm over it; judged once the gripper left"),
    (1120, "nominal", "small", 0, "10 mm cubes: the holder window showed 0.09 of a held "
     "one, under EMPTY; a place is seen where the hand let go of it, by its creases"),
    (1156, "nominal", "small", 0, "a 19 mm cube picked from against another: the one "
     "behind showed through, and the change fell short of what the pick could make"),
    (1050, "nominal", "small", 0, "15 mm cubes set against each other along x: gripped "
     "off centre, and carried in the traced model too"),
]


@pytest.mark.parametrize(("seed", "level", "family", "most", "why"), QUIET_RUNS,
                         ids=[f"{r[0]}-{r[1]}-{r[2]}" for r in QUIET_RUNS])
@pytest.mark.heavy
def test_fault_free_bench_runs_raise_no_false_detection(seed, level, family, most, why):
    """`lbw bench --count 300 --seed 1` runs with no fault injected: the monitor must not
    see the robot do other than it did (perception/vision/envnodes/search.py regions)."""
    from lbw_engine.cli.bench import run_one

    record = run_one((seed, level, family, None))
    assert record["execution_success"], record
    assert record["monitor_detections"] <= most, why
