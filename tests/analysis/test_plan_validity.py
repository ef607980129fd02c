"""A validity oracle for generated plans: every ordered dependency is kept by the plots.

For each pair of ACHIEVEs with a B-T or B-S dependency (i before j), their lowest
common ancestor in the plan must have them in different items of a $sequence,
i's item first; C-T-only pairs may be in a $parallel. Each ACHIEVE appears once.
"""

from __future__ import annotations

import pytest

from bench.bench_analysis import synthetic_task
from lbw_engine.rules import load_rules
from lbw_engine.understand import RelationTable, analyze, parse_actions


def _plan(n):
    rules = load_rules().analysis
    return analyze(parse_actions(synthetic_task(n), RelationTable(rules.tolerance)), rules)


def _paths(plan):
    """operator name -> path of (parent, plot-item position path) from the root."""
    ops, out = plan["operators"], {}

    def walk(name, path):
        out[name] = path
        plot = ops[name]["plot"]

        def items(p, where):
            if p[0] == "$action":
                if p[1] in ops:
                    walk(p[1], [*path, (name, where)])
                return
            for k, sub in enumerate(p[1:]):
                items(sub, (*where, (p[0], k)))

        items(plot, ())

    walk(plan["root"], [])
    return out


def _ordered(path_i, path_j):
    """True if i must come before j in the plan (a $sequence separates them, i first)."""
    for (op_i, where_i), (op_j, where_j) in zip(path_i, path_j, strict=False):
        if (op_i, where_i) == (op_j, where_j):
            continue
        assert op_i == op_j
        for (kind_i, k_i), (kind_j, k_j) in zip(where_i, where_j, strict=False):
            if (kind_i, k_i) != (kind_j, k_j):
                return kind_i == "$sequence" and k_i < k_j
        return False
    return False


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 11, 16, 27, 40])
def test_synthetic_plans_keep_every_dependency(n):
    result = _plan(n)
    plan = result.plan
    achieves = [name for name, op in plan["operators"].items() if op["class"] == "ACHIEVE"]
    assert len(achieves) == n
    assert plan["operators"][plan["root"]]["class"] == "BUILD"
    paths = _paths(plan)
    assert set(achieves) <= set(paths)
    ops = sorted(result.achieves, key=lambda o: o.lo)
    checked = 0
    for i, a in enumerate(ops):
        for b in ops[i + 1:]:
            if a.base & (b.target | b.special):
                checked += 1
                assert _ordered(paths[a.name], paths[b.name]), (a.name, b.name)
    assert checked >= n // 3  # the structures do depend on each other's blocks


def test_every_put_keeps_its_goal_with_coordinates():
    plan = _plan(11).plan
    for name, op in plan["operators"].items():
        if op["class"] == "PUT":
            goals = [r for r in op["sc_plus"] if r[0] in ("on", "on-multiple")]
            assert len(goals) == 1 and "at" in goals[0][3], name
            moved = goals[0][1]
            support = goals[0][2] if isinstance(goals[0][2], list) else [goals[0][2]]
            assert op["base"] == [moved] and op["target"] == sorted(support), name


# A cube moved more than once (helper round 10): B-B orders the moves of one object.
MOVED_AGAIN = {
    # s to A on the table, then to B: both ACHIEVEs target the table (C-T), and were
    # put in a $parallel, so the robot could leave s at A (v24a)
    "twice-on-table": ("s: {shape: c20, at: [200, 80]}\n",
                       [("s", "table", [-50, 200]), ("s", "table", [80, 300])]),
    # s, then t, then s again onto the plate it stands on (v24c)
    "interleaved": ("p: {shape: plate, at: [0, 200]}\n    s: {shape: c20, on: p}\n"
                    "    t: {shape: c20, at: [200, 300]}\n",
                    [("s", "p", [40, 240]), ("t", "table", [-200, 80]),
                     ("s", "p", [-40, 160])]),
}


def _taught(shapes: str, objects: str, moves) -> tuple[dict, list]:
    """The plan learned (through the oracle recognizer) from picks and places of
    ``moves`` (object, support, at): the plot paths of its operators, and its ACHIEVEs in
    demonstration order."""
    from lbw_engine.see.actions import to_actions
    from perception.world.oracle import oracle_recognizer
    from perception.world.scenario import load_text

    demo = "".join(f"    - pick: {o}\n    - place: {o}\n      on: {on}\n      at: {at}\n"
                   for o, on, at in moves)
    sc = load_text(f"name: taught\nshapes:\n{shapes}"
                   f"teach:\n  objects:\n    {objects}  demonstration:\n{demo}")
    rules = load_rules()
    result = analyze(parse_actions(to_actions(oracle_recognizer(sc, rules)),
                                   RelationTable(rules.analysis.tolerance)), rules.analysis)
    return _paths(result.plan), sorted(result.achieves, key=lambda o: o.lo)


@pytest.mark.parametrize("case", sorted(MOVED_AGAIN))
def test_the_moves_of_one_object_stay_in_their_order(case):
    objects, moves = MOVED_AGAIN[case]
    paths, ops = _taught("  c20: [20, 20, 20]\n  plate: [120, 120, 10]\n", objects, moves)
    again = [(a, b) for i, a in enumerate(ops) for b in ops[i + 1:] if a.base & b.base]
    assert again
    for a, b in again:
        assert _ordered(paths[a.name], paths[b.name]), (a.name, b.name)


# A spot used twice (helper round 11): S-S orders a place after the move off its spot.
SPOT_REUSED = {
    # a to A, a on to B, then b to A: b's ACHIEVE was in a $parallel with a's first,
    # and the robot found A taken (93)
    "moved-on-then-filled": ("a: {shape: c40, at: [-200, 100]}\n"
                             "    b: {shape: brick, at: [200, 100]}\n",
                             [("a", [0, 200]), ("a", [0, 330]), ("b", [0, 200])]),
    # a starts at A; it goes to B and b takes A (a swap through the table)
    "initial-spot-filled": ("a: {shape: c40, at: [0, 200]}\n"
                            "    b: {shape: brick, at: [200, 100]}\n",
                            [("a", [-150, 300]), ("b", [0, 200])]),
    # the spot's next block is a post twice the cube's height: centres 20 mm apart in z
    # (helper review of stop 29: S-S compared z too, and missed it)
    "filled-by-a-taller-block": ("a: {shape: c40, at: [-200, 100]}\n"
                                 "    b: {shape: post, at: [200, 100]}\n",
                                 [("a", [0, 200]), ("a", [0, 330]), ("b", [0, 200])]),
}


@pytest.mark.parametrize("case", sorted(SPOT_REUSED))
def test_a_place_on_a_spot_another_left_comes_after_that_move(case):
    objects, moves = SPOT_REUSED[case]
    paths, ops = _taught("  c40: [40, 40, 40]\n  brick: [60, 30, 30]\n  post: [30, 30, 80]\n",
                         objects, [(o, "table", at) for o, at in moves])
    filler = ops[-1]  # b's ACHIEVE, onto the spot a left
    leaves = next(o for o in ops if "a" in o.base and o.lo == max(
        p.lo for p in ops if "a" in p.base))
    assert _ordered(paths[leaves.name], paths[filler.name]), (leaves.name, filler.name)
