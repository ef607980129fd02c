"""Static balance when the branches of a $parallel are ordered (Fig. 14, inverted arch).

Generated seed 1048 (nominal) puts the plank on its pillar before the two
cubes, which the learned plan lists as a $parallel; its first listed cube goes
on the plank's overhanging end and tipped the plank. The plan is the one the
recognizer learned, stored so the test does not depend on recognition.
"""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.do.balance import steadied, unbalanced
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parent / "data"


def _arch(cubes: dict[str, float]) -> EnvModel:
    """A plank on a 50 mm pillar, its centre 14 mm off the pillar's, cubes at plank x."""
    bodies = {"pillar": Body("block", (50, 50, 50), (0, 0, 25)),
              "plank": Body("plank", (160, 60, 20), (14, 0, 60))}
    for name, x in cubes.items():
        bodies[name] = Body("cube", (40, 40, 40), (14 + x, 0, 90))
    return EnvModel.measured(load_rules(), bodies, (0, 200, 200))


@pytest.mark.parametrize(("cubes", "tips"), [
    ({}, None),
    ({"cube-far": 51}, "plank"),            # the overhanging end alone tips the plank
    ({"cube-near": -52}, None),             # the end over the pillar alone holds
    ({"cube-far": 51, "cube-near": -52}, None),  # both: the taught arch stands
], ids=["Fig14-plank-alone", "Fig14-far-cube-first", "Fig14-near-cube-first",
        "Fig14-both-cubes"])
def test_unbalanced(cubes, tips):
    assert unbalanced(_arch(cubes), margin=2.0) == tips


def test_seed_1048_learned_plan_executes_and_verifies():
    rules = load_rules()
    plan = planmod.load(DATA / "gen-1048-nominal.plan.json")
    result = execute_plan(plan, load(DATA / "gen-1048-nominal.yaml"), rules)
    assert result.success, result.message
    # The cube next to the pillar went onto the plank first (the listed order
    # would have put the overhanging one first).
    puts = [op for op in result.trace.ops
            if op.focus in ("inv2-cube1", "inv2-cube2") and op.goal is not None
            and op.goal[2] > 80]
    pillar = result.trace.model.bodies["inv2-pillar"].position
    first, second = puts[0].goal, puts[-1].goal
    assert puts[0].focus != puts[-1].focus
    assert abs(first[0] - pillar[0]) < abs(second[0] - pillar[0])


def _steps() -> EnvModel:
    """The bottom 40 mm cube of a staircase at x 0; the next one still on the table."""
    bodies = {"s1": Body("cube", (40, 40, 40), (0, 0, 20)),
              "s2": Body("cube", (40, 40, 40), (300, 0, 20))}
    return EnvModel.measured(load_rules(), bodies, (0, 200, 200))


@pytest.mark.parametrize(("xy", "coming", "stays"), [
    ((12.0, 0.0), [], True),                              # one step alone stands
    ((16.0, 0.0), [], True),                              # ... measured 4 mm long too
    ((12.0, 0.0), [(12.0, 0.0, 64000.0)], True),          # with the top step: on the margin
    ((16.0, 0.0), [(12.0, 0.0, 64000.0)], False),         # ... 4 mm long, beyond: moved
    ((4.0, 0.0), [(12.0, 0.0, 64000.0)], True),           # a low staircase keeps its spot
    ((0.0, 16.0), [(0.0, 12.0, 64000.0)], False),         # along y as along x
], ids=["one-step", "one-step-long", "two-steps", "two-steps-long", "low-steps",
        "steps-along-y"])
def test_a_step_carries_what_the_plan_will_put_on_it(xy, coming, stays):
    """Bench 1262 at 2x: a staircase's middle cube measured 4 mm long stood alone; the top
    cube set on it later tipped both off the bottom one (and off the table). The middle
    cube's spot must carry what the plan will still put on it (balance.steadied
    ``coming``): its centre of mass with the top step at least steady-margin inside."""
    model = _steps()
    rules = load_rules().commands
    out, moved = steadied(model, "s2", xy, ["s1"], rules.balance_margin,
                          rules.steady_margin, coming)
    assert (moved == 0.0) == stays, (out, moved)
    if not stays:
        load = [(out[k] * 64000.0 + sum(v * (out[k] + d[k]) for *d, v in coming))
                / (64000.0 * (1 + len(coming))) for k in range(2)]
        assert all(abs(c) <= 20.0 - rules.steady_margin + 1e-6 for c in load), (out, load)


@pytest.mark.heavy
def test_seed_1262_staircase_stands():
    """The learned plan of bench 1262 (stairs, 2x): executed, the staircase stands and
    verifies (the top step and the middle one fell off the table: 'a cube is gone')."""
    rules = load_rules()
    plan = planmod.load(DATA / "gen-1262-2x.plan.json")
    result = execute_plan(plan, load(DATA / "gen-1262-2x.yaml"), rules)
    assert result.success, result.message
    assert any(op.steadied > 0 for op in result.trace.ops)


def test_a_block_put_now_stands_though_what_comes_later_would_ask_otherwise():
    """A 100 mm plank on a 20 mm post with a brick to come 30 mm out: no spot keeps both
    loads' centres of mass inside the post, so the plank alone must stand where it goes
    (it sits there until the brick comes; review of stop 33)."""
    bodies = {"post": Body("post", (20, 20, 40), (0, 0, 20)),
              "plank": Body("plank", (100, 20, 10), (300, 0, 5))}
    model = EnvModel.measured(load_rules(), bodies, (0, 200, 200))
    rules = load_rules().commands
    out, _ = steadied(model, "plank", (0.0, 0.0), ["post"], rules.balance_margin,
                      rules.steady_margin, [(30.0, 0.0, 30.0 * 30 * 30)])
    assert abs(out[0]) <= 10.0 - rules.balance_margin, out


def _final(*rels):
    """A plan whose root's SC+ holds ``rels`` (type, subject, support, at)."""
    from types import SimpleNamespace as NS

    from lbw_engine.do.plan import Relation

    return NS(root="r", operators={"r": NS(sc_plus=tuple(
        Relation(t, s, (o,), at=at, wrt=o if o != "table" else None) for t, s, o, at in rels))})


@pytest.mark.parametrize(("rels", "riding", "want"), [
    # a chain: c on b on a, both to come (offsets add up)
    ([("on", "b", "a", (5, 0, 40)), ("on", "c", "b", (5, 0, 40))], [], [(5, 0), (10, 0)]),
    # b already rides on a: only c is to come, at its offset through b
    ([("on", "b", "a", (5, 0, 40)), ("on", "c", "b", (5, 0, 40))], ["b"], [(10, 0)]),
    # on the table: nothing rests on a
    ([("on", "b", "table", (100, 0, 20))], [], []),
    # a support cycle (a malformed plan): each block counted once, and the walk ends
    ([("on", "b", "a", (5, 0, 40)), ("on", "a", "b", (-5, 0, -40))], [], [(5, 0)]),
], ids=["chain", "already-riding", "table", "cycle"])
def test_what_the_plan_will_still_put_on_a_block(rels, riding, want):
    from lbw_engine.do.placement import to_come

    bodies = {"a": Body("cube", (40, 40, 40), (0, 0, 20)),
              "b": Body("cube", (40, 40, 40), (200, 0, 60 if riding else 20)),
              "c": Body("cube", (40, 40, 40), (-200, 0, 20))}
    if riding:
        bodies["b"] = Body("cube", (40, 40, 40), (0, 0, 60))
    model = EnvModel.measured(load_rules(), bodies, (0, 200, 200))
    got = to_come(_final(*rels), "a", ("on",), model)
    assert sorted((round(x), round(y)) for x, y, _ in got) == sorted(want)
