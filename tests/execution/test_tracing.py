"""Plan tracing (Sec. VII-A): goals, relative PLACE goals, the model, command counts."""

from pathlib import Path

import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.do.listing import format_commands
from lbw_engine.do.tracing import trace
from lbw_engine.errors import InputError
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.rules import load_rules

DATA = Path(__file__).resolve().parent.parent / "data"
RULESET = load_rules()
RULES = RULESET.commands
SIZES = {"short-brick": (40.0, 40.0, 50.0), "planar-brick": (160.0, 60.0, 20.0),
         "medium-brick": (30.0, 30.0, 60.0), "brick": (30.0, 30.0, 50.0),
         "plate": (120.0, 100.0, 10.0), "cube": (40.0, 40.0, 40.0)}


def model_of(objects, extra=()):
    """A model with objects {name: (shape, x, y)} on the table, plus irrelevant ones."""
    bodies = {}
    for name, (shape, x, y) in objects.items():
        s = SIZES[shape]
        bodies[name] = Body(shape, s, (x, y, s[2] / 2))
    for k, (shape, x, y) in enumerate(extra):
        s = SIZES[shape]
        bodies[f"unused-{k}"] = Body(shape, s, (x, y, s[2] / 2), relevant=False)
    return EnvModel.measured(RULESET, bodies, RULES.home)


ARCH = planmod.load(DATA / "inverted-arch.plan.json")
TABLE_PLAN = planmod.load(DATA / "build-table.plan.json")
# Apart from every plank position below (a brick standing in the plank's footprint
# would be inside it, and the fingers gripping it would meet the plank).
ARCH_OBJECTS = {"pillar": ("short-brick", 200, 300), "brick-a": ("medium-brick", 100, 200),
                "brick-b": ("medium-brick", -50, 250)}


def _goals(tr, operation):
    return {op.focus: op.goal for op in tr.ops if op.operation == operation}


@pytest.mark.parametrize("plank_at", [(-150.0, 100.0), (150.0, 60.0), (-200.0, 330.0)],
                         ids=["Fig14-plank-left", "Fig14-plank-right", "Fig14-plank-far"])
def test_relative_place_goals_follow_the_plank(plank_at):
    model = model_of({**ARCH_OBJECTS, "plank": ("planar-brick", *plank_at)})
    tr = trace(ARCH, RULES, model)
    c = RULES.release_clearance
    goals = _goals(tr, "PLACE-ON-BLOCK")
    # The bricks go onto the plank where it lies now (20 mm plank, 60 mm bricks) ...
    assert goals["brick-a"] == pytest.approx((plank_at[0] - 50, plank_at[1], 20 + 30 + c))
    assert goals["brick-b"] == pytest.approx((plank_at[0] + 50, plank_at[1], 20 + 30 + c))
    # ... and the plank onto the pillar, which went to its taught world position.
    assert _goals(tr, "PLACE-ON-TABLE")["pillar"] == pytest.approx((-30, 130, 25 + c))
    assert goals["plank"] == pytest.approx((-30, 130, 50 + 10 + c))
    # The expected final state: the bricks rode along on the plank.
    final = model.settled(["pillar", "plank", "brick-a", "brick-b"])
    assert final["brick-a"] == pytest.approx((-80, 130, 100))
    assert final["brick-b"] == pytest.approx((20, 130, 100))
    supports = model.final_supports(["pillar", "plank", "brick-a", "brick-b"])
    assert supports == {"pillar": ("on", ("table",)), "plank": ("on", ("pillar",)),
                        "brick-a": ("on", ("plank",)), "brick-b": ("on", ("plank",))}


TABLE_OBJECTS = {"brick1": ("brick", 150, 60), "brick2": ("brick", 250, 170),
                 "brick3": ("brick", -250, 330), "brick4": ("brick", -160, 70),
                 "plate1": ("plate", -150, 230)}


def test_build_table_expands_to_45_commands_as_in_the_paper():
    tr = trace(TABLE_PLAN, RULES, model_of(TABLE_OBJECTS))
    assert len(tr.commands) == 45  # Sec. VIII: "Forty-five manipulator commands"
    text = format_commands(tr)
    assert text.count("<<Fetch>>") == 5 and text.count("<<Put>>") == 5
    assert "GOAL-POSITION #f(" in text and "ARM GOAL POSITION #f(" in text
    assert text.count("\n amove #f(") == 30 and text.count("open-hand") == 10


def test_pick_goals_are_retargeted_to_the_measured_objects():
    tr = trace(TABLE_PLAN, RULES, model_of(TABLE_OBJECTS))
    for name, (shape, x, y) in TABLE_OBJECTS.items():
        assert _goals(tr, "PICK")[name] == pytest.approx((x, y, SIZES[shape][2] / 2))


def test_fake_touch_is_a_harmless_reach():
    tr = trace(ARCH, RULES, model_of({**ARCH_OBJECTS, "plank": ("planar-brick", -150, 100)}))
    touch = [op for op in tr.ops if op.operator == "fake01"]
    assert [op.operation for op in touch] == ["REACH", "NO-OP", "WITHDRAW"]
    moves = [c for op in touch for c in op.commands]
    assert [c.name for c in moves] == ["amove"]
    assert moves[0].world[2] == pytest.approx(RULES.approach_height)
    assert moves[0].world[:2] == pytest.approx(ARCH_OBJECTS["brick-b"][1:])


def test_an_irrelevant_object_on_a_goal_spot_is_set_aside_before_the_pick():
    model = model_of(TABLE_OBJECTS, extra=[("cube", -70, 215)])  # on brick2's leg spot
    ops = trace(TABLE_PLAN, RULES, model).ops
    first = next(op for op in ops if op.aside)
    assert first.focus == "brick2"  # before the pick, with the hand empty
    assert [name for _, _, name, _ in first.aside] == ["unused-0"]
    assert "lies where the plan puts 'brick2'" in first.aside[0][0]


def test_unknown_operation_is_bad_input():
    doc = {"root": "f", "operators": {"f": {"class": "FETCH", "base": ["brick1"],
                                            "plot": ["$action", "jump01"]}}}
    plan = planmod.parse(doc, "p.json")
    with pytest.raises(InputError) as exc:
        trace(plan, RULES, model_of({"brick1": ("brick", 0, 100)}))
    assert "JUMP" in exc.value.message and exc.value.file == "p.json"


@pytest.mark.parametrize(
    "doc,needle",
    [
        ({"operators": {}}, "'root'"),
        ({"root": "x", "operators": {}}, "root operator 'x'"),
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": ["$seq"]}}}, "a plot is"),
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": ["$action", "a"]}}},
         "contains itself"),
        ({"root": "a", "operators": {"a": {"class": "PUT", "plot": ["$action", "x"],
                                           "sc_plus": [["on", "b"]]}}}, "a relation is"),
        ({"root": "a", "operators": {"a": {"class": "PUT", "plot": ["$action", "Bad"]}}},
         "neither an operator"),
        # round 15 (cli/j): an empty plot did nothing and the run "verified"; an ACHIEVE
        # named twice was done twice
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": ["$sequence"]}}},
         "at least one PLOT"),
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": [
            "$parallel", ["$action", "b"], ["$sequence"]]},
            "b": {"class": "PUT", "plot": ["$action", "place01"]}}}, "at least one PLOT"),
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": [
            "$sequence", ["$action", "b"], ["$action", "b"]]},
            "b": {"class": "PUT", "plot": ["$action", "place01"]}}}, "in the plots twice"),
        # ... and one recognized action done twice (review of stop 32)
        ({"root": "a", "operators": {"a": {"class": "BUILD", "plot": [
            "$sequence", ["$action", "b"], ["$action", "c"]]},
            "b": {"class": "PUT", "plot": ["$action", "place01"]},
            "c": {"class": "PUT", "plot": ["$action", "place01"]}}},
         "action 'place01' is in the plots twice"),
    ],
    ids=["no-root", "unknown-root", "bad-plot", "cycle", "bad-relation", "bad-leaf",
         "empty-plot", "empty-inner-plot", "operator-twice", "action-twice"],
)
def test_bad_plans_are_input_errors(doc, needle):
    with pytest.raises(InputError) as exc:
        planmod.parse(doc, "plan.json")
    assert needle in exc.value.message and exc.value.file == "plan.json"


def test_an_order_search_backs_out_of_a_dead_end():
    """ordering.feasible_order: branch 2 can be done only before branch 0 (the middle cube
    of a row before its neighbours); the listed order dead-ends, the search does not."""
    from lbw_engine.do.ordering import feasible_order

    def attempt(done, i):
        if i == 2 and 0 in done:
            return None
        return done | {i}

    assert feasible_order(frozenset(), 3, attempt) == [1, 2, 0]
    assert feasible_order(frozenset(), 3, lambda d, i: None) is None
    calls = []
    assert feasible_order(frozenset(), 4, lambda d, i: calls.append(i), trials=5) is None
    assert len(calls) == 4  # every first branch failed: 4 attempts, within the budget
