"""execute.faults (design.md "Scenario file"): strict loading, and the world-side injection."""

from pathlib import Path

import pytest
import yaml

from lbw_engine.errors import InputError
from perception.world.faults import Fault, FaultInjector
from perception.world.physics import World
from perception.world.scenario import load_text

HEAD = """\
name: t
shapes:
  brick: [30, 30, 50]
  plank: [160, 60, 20]
teach:
  objects:
    a: {shape: brick, at: [-100, 100]}
  demonstration:
    - pick: a
    - place: a
      on: table
      at: [0, 150]
execute:
  objects:
    x: {shape: brick, at: [-100, 100]}
    p: {shape: plank, at: [100, 300]}
    y: {shape: brick, at: [60, 300], on: p}
"""
LINE = HEAD.count("\n") + 2  # the line of the first fault


def _faults(*items: str) -> str:
    return HEAD + "  faults:\n" + "".join(f"    - {i}\n" for i in items)


def test_the_three_kinds_load_in_order():
    sc = load_text(_faults("{during: 2, kind: drop}",
                           "{after: 3, kind: displace, object: x, by: [60, -20]}",
                           "{after: 4, kind: remove, object: p}"), "f.yaml")
    assert sc.faults == (Fault("drop", 2, None, (0.0, 0.0), LINE),
                         Fault("displace", 3, "x", (60.0, -20.0), LINE + 1),
                         Fault("remove", 4, "p", (0.0, 0.0), LINE + 2))
    assert load_text(HEAD, "f.yaml").faults == ()


# (case id, fault items, key path, message fragment)
ROWS = [
    ("unknown-kind", ["{after: 1, kind: melt, object: x}"], "execute.faults[0].kind",
     "unknown fault kind"),
    ("drop-with-after", ["{after: 1, kind: drop}"], "execute.faults[0].after",
     "unknown key 'after' for a drop fault"),
    ("displace-without-by", ["{after: 1, kind: displace, object: x}"], "execute.faults[0].by",
     "a displace fault needs 'by'"),
    ("remove-unknown-object", ["{after: 1, kind: remove, object: nope}"],
     "execute.faults[0].object", "unknown object 'nope'"),
    ("count-zero", ["{during: 0, kind: drop}"], "execute.faults[0].during",
     "an ACHIEVE count from 1"),
    ("count-not-integer", ["{during: 1.5, kind: drop}"], "execute.faults[0].during",
     "an ACHIEVE count from 1"),
    ("by-too-far", ["{after: 1, kind: displace, object: x, by: [900, 0]}"],
     "execute.faults[0].by[0]", "900"),
    ("by-one-number", ["{after: 1, kind: displace, object: x, by: [9]}"],
     "execute.faults[0].by", "a list of 2 numbers"),
    ("no-kind", ["{after: 1, object: x}"], "execute.faults[0]", "with 'kind'"),
    ("second-bad", ["{during: 1, kind: drop}", "{after: 1, kind: remove}"],
     "execute.faults[1].object", "a remove fault needs 'object'"),
]


@pytest.mark.parametrize("items,where,fragment", [r[1:] for r in ROWS], ids=[r[0] for r in ROWS])
def test_bad_fault_is_reported_with_its_place(items, where, fragment):
    with pytest.raises(InputError) as info:
        load_text(_faults(*items), "bad.yaml")
    err = info.value
    assert (err.file, err.where) == ("bad.yaml", where)
    assert fragment in err.message
    assert err.line in (LINE, LINE + 1)


def test_faults_must_be_a_list():
    with pytest.raises(InputError) as info:
        load_text(HEAD + "  faults: {during: 1}\n", "bad.yaml")
    assert info.value.where == "execute.faults" and info.value.line == LINE - 1


def _world():
    sc = load_text(HEAD, "f.yaml")
    world = World(sc.execute.objects.values())
    world.settle(0.3)
    return world


def test_displacing_a_support_lets_its_rider_fall():
    world = _world()
    x0 = world.positions()["p"][0]
    assert world.supports()["y"] == ("p",)
    inj = FaultInjector(world, (Fault("displace", 1, "p", (-80.0, 60.0)),), {"p": "p"})
    inj.begin(1)
    t = world.time
    inj.end(1)
    world.settle(1.5)
    assert world.y["p"] == 360.0 and world.positions()["p"][0] == pytest.approx(x0 - 80.0, abs=1)
    assert world.supports()["y"] == ("table",)  # it fell off the plank slid from under it
    assert inj.injected == [{"kind": "displace", "achieve": 1, "t": round(t, 2), "object": "p",
                             "moved_mm": pytest.approx(100.0, abs=1)}]


def test_removing_an_object_takes_it_out_of_the_world():
    world = _world()
    inj = FaultInjector(world, (Fault("remove", 2, "x"),), {"x": "x"})
    inj.begin(1)
    inj.end(1)
    assert "x" in world.names  # tied to the 2nd ACHIEVE, not the 1st
    inj.begin(2)
    inj.end(2)
    assert "x" not in world.names and "x" not in world.positions()
    assert [f["kind"] for f in inj.injected] == ["remove"]


def test_a_displace_past_the_table_edge_is_recorded_as_off_the_table():
    """Fault bench seed 7001: a tower's top brick slid 53 mm left of x = -264 fell off the
    table; for the robot it is gone, like a removed object, and the record says so."""
    world = _world()
    inj = FaultInjector(world, (Fault("displace", 1, "x", (-250.0, 0.0)),
                                Fault("displace", 1, "p", (20.0, 0.0))), {"x": "x", "p": "p"})
    inj.begin(1)
    inj.end(1)
    assert [f.get("off_table", False) for f in inj.injected] == [True, False]


@pytest.mark.parametrize("faults, toppled, spare, expected", [
    ([{"kind": "displace", "relevant": True}], [], False, True),
    ([{"kind": "displace", "relevant": True, "off_table": True}], [], False, False),
    ([{"kind": "displace", "relevant": True, "off_table": True}], [], True, True),
    ([{"kind": "displace", "relevant": False, "off_table": True}], [], False, True),
    ([{"kind": "remove", "relevant": True}], [], False, False),
    ([{"kind": "remove", "relevant": True}], [], True, True),
    ([{"kind": "drop", "relevant": True}], ["b"], False, False),
], ids=["displace", "off-table", "off-table-spare", "off-table-unused", "remove",
        "remove-spare", "toppled"])
def test_which_runs_the_fault_bench_counts_repairable(faults, toppled, spare, expected):
    from lbw_engine.cli.bench_faults import repairable

    assert repairable(faults, toppled, spare) is expected


class _Flying:
    """A world whose arm carries block ``b`` at a peaking speed, and where it lands."""

    def __init__(self, lands_at):
        from types import SimpleNamespace as NS

        self.time, self.names, self.lands_at = 0.0, ["b"], lands_at
        self.body = NS(velocity=(0.0, 0.0))
        self.shapes = {"b": NS(body=self.body)}
        self.grippers = [NS(kind="arm", holding="b", opening=40.0, position=(0.0, 200.0, 150.0),
                            open=lambda width: setattr(self.grippers[0], "holding", None))]

    def positions(self):
        return {"b": self.lands_at}

    def carry(self, speed, along=(1.0, 0.0), dt=0.1):
        """One step of the carry at ``speed`` (mm/s) in direction ``along`` over the table."""
        x, y, z = self.grippers[0].position
        self.time += dt
        self.grippers[0].position = (x + along[0] * speed * dt, y + along[1] * speed * dt, z)
        self.body.velocity = (along[0] * speed, 0.0)


@pytest.mark.parametrize("lands_at, off", [((-1700.0, 246.0, -1.2e5), True),
                                           ((-120.0, 200.0, 25.0), False)],
                         ids=["thrown-off-the-table", "on-the-table"])
def test_a_drop_that_throws_the_block_off_the_table_is_recorded_so(lands_at, off):
    """Fault seed 9005 (drop + displace): the brick let go mid-transfer flew past the
    table's edge. For the robot it is gone like a removed object; the bench counted the
    run repairable, as the drop's record did not say so."""
    world = _Flying(lands_at)
    inj = FaultInjector(world, (Fault("drop", 1, None),), {"b": "b"})
    inj.begin(1)
    for v in (100.0, 300.0, 500.0, 400.0):  # past the carry's peak speed: let go
        world.carry(v)
        inj.on_step(world)
    assert [f["kind"] for f in inj.injected] == ["drop"]
    inj.end(1)
    assert inj.injected[0].get("off_table", False) is off


@pytest.mark.parametrize("along", [(1.0, 0.0), (0.0, 1.0), (0.6, -0.8)],
                         ids=["along-x", "along-y", "slanted"])
def test_a_drop_fires_past_the_carry_peak_whichever_way_it_goes(along):
    """Helper round 8 (v42, v61): the simulation's bodies move in x-z and the gripper
    carries them along y itself, so a carry along y never made the body's x speed peak,
    and the drop never fired ("the robot did not get that far"). The carry's speed over
    the table is the gripper's, along x and y."""
    world = _Flying((-120.0, 200.0, 25.0))
    inj = FaultInjector(world, (Fault("drop", 1, None),), {"b": "b"})
    inj.begin(1)
    for v in (100.0, 300.0, 500.0):  # speeding up: held
        world.carry(v, along)
        inj.on_step(world)
    assert inj.injected == []
    world.carry(400.0, along)  # past the peak: let go
    inj.on_step(world)
    assert [f["kind"] for f in inj.injected] == ["drop"]


def test_a_block_moved_along_y_onto_another_stops_against_it():
    """An outside agent moves a block along y onto another's place: it stops against it
    (helper round 10, z07: pymunk has no y, and a cube moved into a post was popped up
    inside or onto it; the cameras read the two as one block and both were 'gone').
    The plank p spans y 270..330; the 30 mm brick is moved from y 100 by 200."""
    sc = load_text(HEAD.replace("x: {shape: brick, at: [-100, 100]}",
                                "x: {shape: brick, at: [100, 100]}"), "f.yaml")
    world = World(sc.execute.objects.values())
    world.settle(0.3)
    world.displace("x", (0.0, 200.0))
    world.settle(0.5)
    assert world.extent("x", 1)[1] == pytest.approx(world.extent("p", 1)[0], abs=0.5)
    assert world.positions()["x"][2] == pytest.approx(25.0, abs=1.0)  # on the table


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 6])
def test_a_nudge_slides_a_used_block_a_few_mm_once_the_structure_is_built(seed):
    """The fault bench's nudge (stop 33): after the last ACHIEVE, one block the plan uses
    moves 6-12 mm along one axis, past the 5 mm position tolerance."""
    import numpy as np

    from lbw_engine.cli.bench_faults import NUDGE_MM, draw_faults
    from lbw_engine.do import plan as planmod
    from lbw_engine.do.monitor import UNIT_CLASS
    from lbw_engine.paths import bundled_scenario
    from perception.world.scenario import load

    sc = load(bundled_scenario("tower"))
    plan = planmod.load(Path(__file__).resolve().parent.parent / "data" / "tower.plan.json")
    units = sum(1 for op in plan.operators.values() if op.cls == UNIT_CLASS)
    lines, extra = draw_faults("nudge", sc, plan, np.random.default_rng(seed))
    assert extra == "" and len(lines) == 1
    fault = yaml.safe_load(lines[0])
    assert fault["kind"] == "displace" and fault["after"] == units
    assert fault["object"] in sc.execute.objects
    moved = [abs(v) for v in fault["by"] if v != 0]
    assert len(moved) == 1 and NUDGE_MM[0] - 0.5 <= moved[0] <= NUDGE_MM[1] + 0.5


def test_a_displace_records_how_far_its_object_went_when_a_neighbour_stops_it():
    """Along y a displaced block stops at the first block it meets (pymunk has no y); the
    record says how far it went, so the fault bench does not count a nudge that moved a
    wedged cube 3 mm as a fault the monitor missed (fault bench 7000)."""
    text = HEAD.replace("    y: {shape: brick, at: [60, 300], on: p}\n",
                        "    c1: {shape: brick, at: [-200, 200]}\n"
                        "    c2: {shape: brick, at: [-200, 234]}\n")
    world = World(load_text(text, "f.yaml").execute.objects.values())
    world.settle(0.3)
    inj = FaultInjector(world, (Fault("displace", 1, "c1", (0.0, 9.0)),), {"c1": "c1"})
    inj.begin(1)
    inj.end(1)
    assert inj.injected[0]["moved_mm"] == pytest.approx(4.0, abs=0.2)


@pytest.mark.parametrize("by", [(0.0, 120.0), (0.0, -350.0), (80.0, 0.0)],
                         ids=["past-y-400", "past-y-0", "past-x-300"])
def test_a_block_slid_past_the_tables_edge_falls(by):
    """Helper round 22 (f20, f24): pymunk's table is a slab along all of y, so a cube slid
    past a y edge stood in the air and the robot picked it back (exit 0)."""
    text = HEAD.replace("    y: {shape: brick, at: [60, 300], on: p}\n",
                        "    c1: {shape: brick, at: [250, 330]}\n")
    world = World(load_text(text, "f.yaml").execute.objects.values())
    world.settle(0.3)
    world.displace("c1", by)
    world.settle(1.0)
    assert world.positions()["c1"][2] < -100.0
