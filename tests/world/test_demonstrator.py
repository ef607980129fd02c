"""The demonstrator's motion has the properties the recognizer relies on (Sec. V-B)."""

import math
from pathlib import Path

import numpy as np
import pytest

from lbw_engine.rules import load_rules
from perception.world.demonstrator import Demonstration, min_jerk
from perception.world.groundtruth import expected_operations, ground_truth
from perception.world.hand import Gripper
from perception.world.physics import World
from perception.world.scenario import load, load_text

RULES = load_rules()

ROOT = Path(__file__).parents[2] / "scenarios"


@pytest.fixture(scope="module")
def table():
    """The Build-Table demonstration, played once, with the hand's path per frame."""
    sc = load(ROOT / "build-table.yaml")
    demo = Demonstration(sc)
    path = []
    for t, scene in demo:
        hand = [b for b in scene if b.kind == "hand"]
        path.append((t, demo.hand.position if hand else None))
    return sc, demo, path


def _speeds(path, t0, t1):
    """Hand speeds (mm/s) between frames inside [t0, t1]."""
    pts = [(t, p) for t, p in path if t0 <= t <= t1 and p is not None]
    return [math.dist(a[1], b[1]) / (b[0] - a[0]) for a, b in zip(pts, pts[1:], strict=False)]


def test_min_jerk_profile():
    assert min_jerk(0.0) == 0.0 and min_jerk(1.0) == 1.0 and min_jerk(0.5) == pytest.approx(0.5)


def test_hand_absent_at_start_and_end(table):
    _, _, path = table
    assert path[0][1] is None and path[-1][1] is None
    assert any(p is not None for _, p in path)


def test_transfers_are_fast_and_local_motions_slow(table):
    sc, demo, path = table
    for op in ground_truth(sc, RULES, demo):
        speeds = _speeds(path, op.t_start, op.t_end)
        if op.motion == "Transfer":
            assert max(speeds) > 150.0, op  # Table IV: well above V_H = 50 mm/s
        else:
            assert np.median(speeds) < 50.0, op


def test_descent_is_slow_downward_and_starts_within_search_reach(table):
    sc, demo, _ = table
    lay = sc.teach.layout()
    for i, step in enumerate(sc.demonstration):
        seg = next(s for s in demo.segments if s.step == i and s.phase == "approach")
        speed = math.dist(seg.p0, seg.p1) / (seg.t1 - seg.t0)
        assert 10.0 < speed < 50.0 / 1.875  # mean; the minimum-jerk peak stays under 50
        drop = seg.p0[2] - seg.p1[2]
        slant = math.dist(seg.p0[:2], seg.p1[:2])
        assert drop > 60.0 and 0.0 < slant < drop  # down, but not exactly vertical
        top = (step.dest[2] - lay.size[step.obj][2] / 2 if step.kind == "place"
               else lay.center[step.obj][2] + lay.size[step.obj][2] / 2)
        assert seg.p0[2] - top < 180.0  # the 4 x 45 mm visual search reaches the target
        lay = sc.states[i]


def test_same_seed_same_frames_other_seed_other_frames():
    text = (ROOT / "arch.yaml").read_text()
    a = [scene for _, scene in Demonstration(load_text(text))][:400:37]
    b = [scene for _, scene in Demonstration(load_text(text))][:400:37]
    c = [scene for _, scene in Demonstration(load_text(text.replace("seed: 5", "seed: 6")))]
    assert a == b
    assert a != c[:400:37]


def test_ground_truth_build_table_is_fig20():
    sc = load(ROOT / "build-table.yaml")
    ops = expected_operations(sc, RULES)
    assert len(ops) == 21 and ops[-2:] == ["PLACE-ON-BLOCK", "WITHDRAW"]
    assert ops[:4] * 4 == ops[:16] == ["REACH", "PICK", "REACH-WITH-OBJ", "PLACE-ON-TABLE"] * 4


def test_ground_truth_inverted_arch_is_fig12():
    fig12 = ("reach pick reach-with-obj place-on-table reach pick reach-with-obj place-on-block "
             "reach no-op reach pick reach-with-obj place-on-block reach pick reach-with-obj "
             "place-on-block withdraw").upper().split()
    assert expected_operations(load(ROOT / "inverted-arch.yaml"), RULES) == fig12


def test_ground_truth_times_tile_the_demonstration():
    sc = load(ROOT / "place-and-align.yaml")
    demo = Demonstration(sc)
    truth = ground_truth(sc, RULES, demo)
    assert [o.operation for o in truth] == expected_operations(sc, RULES)
    for a, b in zip(truth, truth[1:], strict=False):
        assert a.t_end == pytest.approx(b.t_start) and a.t_start < a.t_end
    align = truth[7].fine
    assert [f.operation for f in align] == ["ALIGN"]
    assert truth[7].t_start < align[0].t_start < align[0].t_end < truth[7].t_end
    assert ["on", "block2", "table"] in truth[7].final_relations
    assert ["holding", "hand", "block2"] in truth[7].initial_relations


def test_gripper_closing_on_nothing_holds_nothing():
    sc = load(ROOT / "arch.yaml")
    w = World(sc.teach.objects.values())
    g = w.add_gripper(Gripper((0.0, 200.0, 40.0), opening=80.0))
    g.close()
    w.settle(1.5)
    assert g.holding is None and g.opening == 0.0


def test_gripper_grasps_lifts_and_releases_a_block():
    sc = load(ROOT / "arch.yaml")
    w = World(sc.teach.objects.values())
    x, y, z = sc.teach.objects["left"].center
    g = w.add_gripper(Gripper((x, y, z + 100.0), opening=60.0))
    for target in ((x, y, z), None, (x + 50.0, y, z + 80.0)):
        if target is None:
            g.close()
        else:
            g.move_to(target)
        w.settle(1.0)
    assert g.holding == "left"
    assert w.positions()["left"][2] == pytest.approx(z + 80.0, abs=1.0)
    assert ["holding", "hand", "left"] in w.relations(RULES.roles)
    g.move_to((x + 50.0, y, z - 0.1))
    w.settle(1.0)
    g.open(60.0)
    w.settle(1.0)
    assert g.holding is None and ["on", "left", "table"] in w.relations(RULES.roles)


@pytest.mark.parametrize("name", ["cubes-touching-along-x", "staircase-x-touching",
                                  "tiny-row-x-touching"])
def test_blocks_laid_touching_end_where_the_scenario_says(name):
    """Helper round 8 (v66, v23, v14): blocks laid touching along x. Let down flush, each
    shaking with the approach's tremor until its bottom passed the neighbour's top,
    caught the neighbour's corner and slid 4-23 mm, so the cameras saw another structure
    than the symbolic states the run is scored on. Every block ends within 4 mm of its
    place in the scenario's last state."""
    sc = load(Path(__file__).parent / "data" / f"{name}.yaml")
    demo = Demonstration(sc)
    for _ in demo:
        pass
    final = sc.states[-1].center
    for obj, at in demo.world.positions().items():
        assert math.dist(at, final[obj]) < 4.0, (obj, at, final[obj])


CARRIES = """\
name: carries
shapes:
  base: BASE
  rider: RIDER
teach:
  objects:
    a: {shape: base, at: [-100, 200]}
    b: {shape: rider, on: a}
  demonstration:
    - pick: a
    - place: a
      on: table
      at: [100, 100]
execute:
  objects:
    x: {shape: base, at: [200, 300]}
"""


@pytest.mark.parametrize("base,rider", [
    ("[30, 30, 30]", "[30, 30, 30]"), ("[30, 30, 30]", "[30, 30, 20]"),
    ("[30, 30, 30]", "[20, 20, 20]"),
    # the rider reaches past the block along x: the fingers close along y (v48v)
    ("[30, 40, 30]", "[40, 30, 30]")],
    ids=["equal-cube", "as-wide-block", "narrower-cube", "rider-wider-along-x"])
def test_a_block_picked_with_one_on_it_carries_it(base, rider):
    """The jaws close on the picked block and what rests on it rides along; a rider as
    wide as the block between the jaws is not held in its place (round 14, v48p: the
    hand held the top cube of two and the one it was told to pick stayed)."""
    sc = load_text(CARRIES.replace("BASE", base).replace("RIDER", rider), "carries.yaml")
    demo = Demonstration(sc)
    for _ in demo:
        pass
    pos = demo.world.positions()
    assert pos["a"][:2] == pytest.approx((100.0, 100.0), abs=3.0)
    assert pos["b"][:2] == pytest.approx((100.0, 100.0), abs=3.0)
    assert demo.world.supports()["b"] == ("a",)
