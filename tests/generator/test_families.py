"""Scenario families (issue #12): each draws valid, loadable, buildable scenarios of its class."""

import math
from pathlib import Path

import pytest

from lbw_engine.cli import main
from lbw_engine.cli.bench import LEVELS, tasks
from lbw_engine.errors import InputError
from lbw_engine.report.families import format_families, summarize_families
from lbw_engine.report.metrics import wilson
from perception.world.generator import FAMILIES, distinguishable, family_of, generate, stands
from perception.world.scenario import load, load_text

SEEDS = (0, 1, 2)


def _supports(step):
    return [s for s in step.on if s != "table"]


def _neighbour_gaps(sc):
    """Gaps (axis, mm) between boxes resting on the table side by side at the end."""
    end = sc.states[-1]
    on_table = [n for n in end.center if end.support[n] == ("table",)]
    out = []
    for i, a in enumerate(on_table):
        for b in on_table[i + 1:]:
            ba, bb = end.bounds(a), end.bounds(b)
            for axis in (0, 1):
                other = 1 - axis
                if min(ba[other][1], bb[other][1]) > max(ba[other][0], bb[other][0]):
                    out.append((axis, max(ba[axis][0], bb[axis][0]) -
                                min(ba[axis][1], bb[axis][1])))
    return out


def _steps(sc):
    return [s for s in sc.demonstration if s.kind == "place"]


# family -> what every scenario of it must contain (the class of issue #12 it covers)
CLASS = {
    "classic": lambda sc: len(_steps(sc)) >= 2,
    "axis": lambda sc: any(len(_supports(s)) >= 1 or s.at for s in _steps(sc)),
    "gaps": lambda sc: any(0 <= g <= 10 for _, g in _neighbour_gaps(sc)),
    "align": lambda sc: any(s.align for s in _steps(sc)),
    "small": lambda sc: min(min(v) for v in sc.shapes.values()) <= 20,
    "pillars": lambda sc: any(v[2] >= 110 and max(v[:2]) <= 18 for v in sc.shapes.values()),
    "beams": lambda sc: {(180, 30), (30, 180)} <= {tuple(v[:2]) for v in sc.shapes.values()},
    "bridge": lambda sc: any(len(_supports(s)) == 2 and all(
        sc.states[-1].support[x] != ("table",) for x in _supports(s)) for s in _steps(sc)),
    "three-supports": lambda sc: any(len(_supports(s)) == 3 for s in _steps(sc)),
    "stairs": lambda sc: any(_supports(s) and s.at and math.dist(
        s.at, sc.states[-1].center[_supports(s)[0]][:2]) >= 6 for s in _steps(sc)),
    "stacked-start": lambda sc: any(o.on != ("table",) for w in (sc.teach, sc.execute)
                                    for o in w.objects.values()),
    "rearrange": lambda sc: any(sc.teach.objects[s.obj].on != ("table",)
                                for s in sc.demonstration if s.kind == "pick"),
    # a base picked with its rider on it, or small blocks a block apart
    "twins": lambda sc: any(o.on == (s.obj,) for s in sc.demonstration if s.kind == "pick"
                            for o in sc.teach.objects.values()) or (
        min(min(v) for v in sc.shapes.values()) <= 20
        and any(g >= 10 for _, g in _neighbour_gaps(sc))),
}


def test_every_family_has_a_class_check():
    assert set(CLASS) == set(FAMILIES)


@pytest.mark.parametrize("family,seed", [(f, s) for f in FAMILIES for s in SEEDS])
def test_family_scenario_is_valid_and_of_its_class(family, seed):
    g = generate(seed, "2x", family=family)
    assert g.family == family and generate(seed, "2x", family=family).text == g.text
    sc = load_text(g.text, "gen.yaml")  # the loader: format, bounds, overlaps, the replay
    assert sc.noise.tremor == pytest.approx(2 * load_text(
        generate(seed, family=family).text).noise.tremor)
    assert CLASS[family](sc), g.text
    sizes = list(sc.shapes.values())
    assert all(distinguishable(a, b) for i, a in enumerate(sizes) for b in sizes[i + 1:])
    tops = [c[2] + sc.shapes[sc.teach.objects[n].shape][2] / 2
            for n, c in sc.states[-1].center.items()]
    tops += [o.center[2] + o.size[2] / 2 for w in (sc.teach, sc.execute)
             for o in w.objects.values()]
    assert max(tops) <= 120
    assert sorted(o.shape for o in sc.teach.objects.values()) == \
        sorted(o.shape for o in sc.execute.objects.values())


def test_tight_gaps_run_along_both_axes_and_rows_run_along_both_axes():
    """The demonstrator's wrist turns (perception.world.wrist): 0-10 mm gaps along x too."""
    gaps = [g for s in range(24) for g in _neighbour_gaps(generate(s, family="gaps").scenario())]
    assert min(g for axis, g in gaps if axis == 1) <= 2
    assert min(g for axis, g in gaps if axis == 0) <= 2
    axes = {axis for s in range(12) for axis, _ in
            _neighbour_gaps(generate(s, family="axis").scenario())}
    assert axes == {0, 1}


def test_align_slides_onto_every_face():
    faces = {s.align.face for seed in range(12) for s in _steps(generate(seed, family="align")
                                                                 .scenario()) if s.align}
    assert faces == {"north", "south", "east", "west"}


@pytest.mark.parametrize("family", [f for f in FAMILIES if f != "classic"])
def test_family_demonstration_builds_its_structure(family):
    """Physics under the demonstrator's hand builds the replayed structure, at rest."""
    assert stands(generate(4, family=family).scenario())


def test_stairs_demonstrated_at_4x_stand():
    """Bench seed 1065 at 4x: three stairs set off by 12 mm each held their top two 2 mm
    inside the lowest one's edge, and the hand's tremor made the stack fall while it was
    demonstrated; the bench then expected a place where a block was seen to vanish.
    Stairs are now simulated under the level's tremor before they are kept."""
    assert stands(generate(1065, "4x", family="stairs").scenario())


def test_gaps_are_kept_only_where_the_demonstration_ends_as_written():
    """Bench seed 1151 at 2x: a cube meant for 1 mm beside its neighbour landed on the
    neighbour's edge and slid 16 mm off, and the next one, meant for 9 mm beside it, then
    overlapped it; the bench expected places the demonstration did not make. Gaps are
    simulated under the level's tremor before they are kept. Since stop 27 the
    demonstrator lets a block down clear of a neighbour it would touch, with a steady
    hand among its neighbours, and that draft ends as written too."""
    slid = load(Path(__file__).parent / "data" / "gaps-1151-slid.yaml")
    assert stands(slid)
    assert stands(generate(1151, "2x", family="gaps").scenario())
    # the check can fail: the demonstration never ends within 0.01 mm of the plan
    assert not stands(slid, tolerance=0.01)
    # a beam set on a post with its centre 50 mm past it would tip off: since stop 29
    # the scenario is refused when loaded (Layout.check_box), before any simulation
    with pytest.raises(InputError, match="would tip off 'p'"):
        load(Path(__file__).parent / "data" / "beam-off-its-post.yaml")


def test_unknown_family_and_structures_outside_classic_are_errors():
    with pytest.raises(ValueError, match="unknown family"):
        generate(1, family="towers")
    with pytest.raises(ValueError, match="classic family only"):
        generate(1, family="gaps", structures=["tower"])


def test_bench_deals_every_family_at_every_level():
    drawn = tasks(300, 1)
    assert drawn == tasks(300, 1) and drawn[0] == (1000, "nominal", "classic")
    seen = {(level, fam) for _, level, fam in drawn}
    assert seen == {(level, fam) for level in LEVELS for fam in FAMILIES}
    assert [family_of(i, ("a", "b")) for i in range(7)] == ["a"] * 3 + ["b"] * 3 + ["a"]
    assert {f for _, _, f in tasks(30, 2, ("beams", "align"))} == {"beams", "align"}


def _rec(family, level, exact, plan, done, error=False):
    r = {"family": family, "level": level, "exact": exact, "plan_correct": plan,
         "execution_success": done}
    return dict(r, error="boom") if error else r


# (records, family, level, n, crashed, exact, plan, exec)
SUMMARY = [
    ([_rec("gaps", "nominal", True, True, True)] * 3 + [_rec("gaps", "nominal", True, True, False)],
     "gaps", "nominal", 4, 0, 4, 4, 3),
    ([_rec("beams", "4x", False, True, False), _rec("beams", "4x", False, False, False, True)],
     "beams", "4x", 2, 1, 0, 1, 0),
    ([{"level": "2x", "exact": True, "plan_correct": True, "execution_success": True}],
     "classic", "2x", 1, 0, 1, 1, 1),  # records from before families: the classic family
]


@pytest.mark.parametrize("records,family,level,n,crashed,exact,plan,done", SUMMARY)
def test_family_summary_counts(records, family, level, n, crashed, exact, plan, done):
    mixed = records + [_rec("other", level, True, True, True)]
    s = summarize_families(mixed, LEVELS)
    row = s[family][level]
    assert (row["n"], row["crashed"]) == (n, crashed)
    for figure, k in (("exact", exact), ("plan", plan), ("exec", done)):
        assert row[figure] == pytest.approx([k, *wilson(k, n)])
    assert s[family]["all"]["n"] == n and s["other"][level]["n"] == 1
    assert f"{done}/{n} (" in format_families(s)


def test_bench_rejects_an_unknown_family(tmp_path, capsys):
    code = main(["bench", "--count", "1", "--families", "gaps,towers",
                 "--out", str(tmp_path / "b.json")])
    err = capsys.readouterr().err
    assert code == 2 and "--families: unknown family towers" in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("family,seed", [("beams", 1006), ("bridge", 1000), ("rearrange", 1083),
                                         ("small", 1136)])
def test_families_draw_touches_with_a_block_in_hand(family, seed):
    """A touch between a pick and its place: the carried block touches the support it is
    then put on, at the place's spot (assemble._steps), so it is as feasible as the place."""
    sc = load_text(generate(seed, family=family).text)
    steps = sc.demonstration
    carried = [(i, s) for i, s in enumerate(steps) if s.kind == "touch" and i > 0
               and steps[i - 1].kind == "pick"]
    assert carried
    for i, touch in carried:
        place = steps[i + 1]
        assert place.kind == "place" and place.obj == steps[i - 1].obj
        assert place.on == (touch.obj,)


@pytest.mark.parametrize("family,seed", [("bridge", 1005), ("rearrange", 1024),
                                         ("three-supports", 1009)])
def test_families_draw_an_execution_object_lying_on_a_goal_spot(family, seed):
    """Helper round 5 (t15, t29): something lies where the plan builds, and the robot must
    set it aside first (assemble._block_a_goal, do/setaside.py clear_goal)."""
    import re

    text = generate(seed, family=family).text
    blocker = re.search(r"; (x-[\w-]+) lies on a goal spot", text).group(1)
    sc = load_text(text)
    at = sc.execute.objects[blocker].center
    size = sc.shapes[sc.execute.objects[blocker].shape]
    final = sc.states[-1].center
    assert any(abs(at[0] - c[0]) < (size[0] + sc.shapes[sc.teach.objects[n].shape][0]) / 2
               and abs(at[1] - c[1]) < (size[1] + sc.shapes[sc.teach.objects[n].shape][1]) / 2
               for n, c in final.items() if n != blocker[2:])


@pytest.mark.parametrize("family,seed", [("small", 1050), ("pillars", 1268), ("bridge", 1059)])
def test_families_set_an_execution_object_against_another(family, seed):
    """Helper round 9 (w42-w100): execution objects in side contact, along x or y. The
    robot grips across the free side, off centre if the block is narrower than the
    fingers (do/jaws.py offsets), and its watch names the block it took
    (assemble._touch_a_neighbour)."""
    import re

    text = generate(seed, family=family).text
    moved, other = re.search(r"; (x-[\w-]+) is set against (x-[\w-]+)", text).groups()
    sc = load_text(text)
    a, b = sc.execute.objects[moved], sc.execute.objects[other]
    sa, sb = sc.shapes[a.shape], sc.shapes[b.shape]
    gaps = [abs(a.center[k] - b.center[k]) - (sa[k] + sb[k]) / 2 for k in (0, 1)]
    assert sorted(gaps)[0] < 0 and abs(sorted(gaps)[1]) < 1e-6  # in contact on one side


def test_gaps_draws_grids_tight_on_both_axes():
    """A 2x2 grid 0-10 mm apart leaves the last cube's fingers no room either way; the
    person's fingertips squeeze in (hand.Gripper.soft), so such grids are drawn. They
    were redrawn as rows until the demonstrator could place them (helper round 10)."""
    from perception.world.wrist import hold_axis

    tight = 0
    for seed in range(24):
        sc = generate(seed, family="gaps").scenario()
        holds = [i for i, s in enumerate(sc.demonstration) if s.kind != "place"]
        tight += any(hold_axis(sc, i) is None for i in holds)
    assert tight >= 4


@pytest.mark.parametrize("seed", [1034, 1213, 1287])
def test_rearrange_draws_a_deck_that_starts_across_two_piers(seed):
    """Helper round 11 (152, 157): a block across two others in an initial layout. The
    rearrange family takes such a deck off its piers and stands a pier on it; the deck
    starts on both piers in both layouts (assemble._layout: one footprint, the piers
    under its ends), and everything stands as the loader replays it."""
    sc = load_text(generate(seed, family="rearrange").text)
    decks = [n for n, o in sc.teach.objects.items() if o.shape == "deck"]
    assert decks
    for w in (sc.teach, sc.execute):
        deck = next(o for o in w.objects.values() if o.shape == "deck")
        assert len(deck.on) == 2
        ends = sorted(w.objects[p].center[0] for p in deck.on)
        assert ends[1] - ends[0] >= 25 + 10  # the table shows between the piers
    assert sc.demonstration[0].obj in decks or sc.demonstration[1].obj in decks


def _close_small_pairs(objects, shapes):
    """Pairs of blocks at most 20 mm wide lying on the table 6-12 mm apart, in line."""
    small = {n: o for n, o in objects.items() if o.on == ("table",)
             and max(shapes[o.shape][:2]) <= 20}
    out = []
    for a, oa in small.items():
        for b, ob in small.items():
            sa, sb = shapes[oa.shape], shapes[ob.shape]
            for k in (0, 1):
                gap = abs(oa.center[k] - ob.center[k]) - (sa[k] + sb[k]) / 2
                if a < b and oa.center[1 - k] == ob.center[1 - k] and 6 <= gap <= 12:
                    out.append((a, b, "xy"[k]))
    return out


@pytest.mark.parametrize("family,seed,level", [("small", 1013, "2x"), ("twins", 1075, "nominal"),
                                               ("pillars", 1015, "nominal")])
def test_families_start_small_blocks_in_a_close_row(family, seed, level):
    """Helper round 20: 15 mm cubes lying 10 mm apart; the person's approach began nearer
    a neighbour than its block (assemble._row_up_small, in teach and execute layouts)."""
    sc = load_text(generate(seed, level, family=family).text)
    pairs = _close_small_pairs(sc.teach.objects, sc.shapes) + \
        _close_small_pairs(sc.execute.objects, sc.shapes)
    assert pairs


@pytest.mark.parametrize("family,seed,level", [("gaps", 1007, "2x"), ("pillars", 1016, "2x"),
                                               ("beams", 1019, "2x")])
def test_families_touch_a_block_already_placed(family, seed, level):
    """Helper round 20 (g3003): an empty hand touches a block placed earlier, with nothing
    on it yet, before the next pick (assemble._touch_a_placed)."""
    steps = load_text(generate(seed, level, family=family).text).demonstration
    touched = [i for i, s in enumerate(steps) if s.kind == "touch"
               and any(p.kind == "place" and p.obj == s.obj for p in steps[:i])]
    assert touched
    i = touched[0]
    assert steps[i + 1].kind == "pick" and steps[i - 1].kind == "place"  # the hand is empty
    assert not any(p.kind == "place" and steps[i].obj in p.on for p in steps[:i])  # top free
