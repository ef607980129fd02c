"""Sec. VI on the paper's examples: Fig. 12 → Fig. 17 and Fig. 14; Fig. 20/21 → Fig. 22; Fig. 16.

The fixtures were written by hand from the figures (tests/data/*.actions.json).
Fig. 14 prints the table as table0; the fixtures use design.md's name `table`.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.bench_analysis import TABLE, TaskWriter, on
from lbw_engine.rules import load_rules
from lbw_engine.understand import RelationTable, analyze, analyze_file, parse_actions

DATA = Path(__file__).resolve().parent.parent / "data"


def seq(*names):
    """($sequence ($action a) ...)."""
    return ["$sequence", *(["$action", n] for n in names)]


def par(*names):
    """($parallel ($action a) ...)."""
    return ["$parallel", *(["$action", n] for n in names)]


@pytest.fixture(scope="module")
def fig12():
    return analyze_file(DATA / "fig12-inverted-arch.actions.json").plan


FIG17 = [
    ("build03", seq("achieve01", "build02")),
    ("achieve01", seq("fetch01", "put01")),
    ("build02", seq("build01", "pachieve01")),
    ("build01", par("achieve03", "achieve02")),
    ("pachieve01", ["$action", "achieve04"]),
    ("achieve03", seq("fetch03", "put03")),
    ("achieve02", seq("fetch02", "put02")),
    ("achieve04", seq("fetch04", "put04")),
]


@pytest.mark.parametrize("name,plot", FIG17, ids=[f"Fig17-{n}" for n, _ in FIG17])
def test_fig17_plots(fig12, name, plot):
    assert fig12["operators"][name]["plot"] == plot


def test_fig17_root_and_removed_fake(fig12):
    assert fig12["root"] == "build03"
    leaves = {a[1] for op in fig12["operators"].values() for a in op["plot"][1:]
              if isinstance(a, list) and a[0] == "$action"}
    assert {"reach03", "no01"}.isdisjoint(leaves)
    assert "fake01" not in fig12["operators"]


def rel(rtype, subject, obj, at, wrt):
    """A relation in plan.json form."""
    return [rtype, subject, obj, {"at": at, "wrt": wrt}]


FIG14 = [
    ("class", "PACHIEVE"),
    ("base", ["planar-brick2"]),
    ("target", ["short-brick1"]),
    ("special", ["medium-brick3", "medium-brick4"]),
    ("sc_plus", [rel("on", "planar-brick2", "short-brick1", [-16.0, 1.8, 37.7], "short-brick1")]),
    ("sc_minus", [rel("on", "planar-brick2", "table", [121.0, 284.3, 12.7], "table")]),
    ("sp", [rel("on", "medium-brick3", "planar-brick2", [-16.5, 15.3, 42.7], "planar-brick2"),
            rel("on", "medium-brick4", "planar-brick2", [34.3, -42.4, 42.7], "planar-brick2")]),
    ("next", []),
    ("plot", ["$action", "achieve04"]),
]


@pytest.mark.parametrize("slot,value", FIG14, ids=[f"Fig14-{s}" for s, _ in FIG14])
def test_fig14_pachieve01(fig12, slot, value):
    assert fig12["operators"]["pachieve01"][slot] == value


def test_fig14_si_without_the_hand(fig12):
    # The literal SI formula also keeps the hand's holding/held-by (made, then undone);
    # Fig. 14 prints only the relations among blocks, which must match exactly.
    si = [r for r in fig12["operators"]["pachieve01"]["si"] if "hand" not in r[:3]]
    assert si == [rel("on", "medium-brick3", "planar-brick2", [-16.5, 15.3, 42.7], "planar-brick2"),
                  rel("on", "medium-brick4", "planar-brick2", [34.3, -42.4, 42.7], "planar-brick2"),
                  rel("on", "short-brick1", "table", [-20.7, 126.6, 25.0], "table")]


@pytest.fixture(scope="module")
def fig20():
    return analyze_file(DATA / "fig20-build-table.actions.json").plan


LEGS = ["brick186", "brick187", "brick188", "brick190"]
FIG22 = [  # (operator, slot, value); the paper's gensym names map to ours in order
    ("build02", "class", "BUILD"),
    ("build02", "base", sorted(["plate189", *LEGS])),
    ("build02", "target", ["table"]),
    ("build02", "special", []),
    ("build02", "next", []),
    ("build02", "plot", seq("build01", "achieve05")),
    ("build01", "base", LEGS),
    ("build01", "target", ["table"]),
    ("build01", "special", []),
    ("build01", "next", ["achieve05"]),
    ("build01", "plot", par("achieve04", "achieve03", "achieve02", "achieve01")),
    ("achieve05", "base", ["plate189"]),
    ("achieve05", "target", LEGS),
    ("achieve05", "special", []),
    ("achieve05", "next", []),
    ("achieve05", "plot", seq("fetch05", "put05")),
]


@pytest.mark.parametrize("name,slot,value", FIG22, ids=[f"Fig22-{n}-{s}" for n, s, _ in FIG22])
def test_fig22_top_two_levels(fig20, name, slot, value):
    assert fig20["root"] == "build02"
    assert fig20["operators"][name][slot] == value


def test_fig22_seventeen_upper_operators(fig20):
    # Sec. VIII: "The total number of upper-level operators ... was 17."
    assert len(fig20["operators"]) == 17


def test_fig22_put_keeps_the_goal_relation(fig20):
    # Execution (issue 6) reads PUT goals from sc_plus: the on-multiple with its :at.
    put = fig20["operators"]["put05"]
    assert put["base"] == ["plate189"] and put["target"] == LEGS
    goal = [r for r in put["sc_plus"] if r[0] == "on-multiple"]
    assert goal == [["on-multiple", "plate189", ["brick190", "brick186", "brick187", "brick188"],
                     {"at": [-25.1, 151.0, 59.8]}]]


def fig16_task():
    """Fig. 16's example: three supports set in parallel, then a plate on them, then a top.

    The supports go onto three blocks already in place (pedestals), so they share no
    target (no C-T) and only the B-T closure searched back from ACHIEVE05 orders them.
    """
    w = TaskWriter()
    for k, name in enumerate(["a", "b", "c"]):
        w.achieve(name, on(name, TABLE, [0.0, 300.0 + 40 * k, 25.0]),
                  [on(name, f"pedestal{k}", [0.0, 0.0, 50.0])])
    w.achieve("plate", on("plate", TABLE, [200.0, 300.0, 5.0]),
              [on("plate", ["a", "b", "c"], [0.0, 100.0, 110.0])])
    w.achieve("top", on("top", TABLE, [250.0, 300.0, 25.0]),
              [on("top", "plate", [0.0, 0.0, 35.0])])
    rules = load_rules().analysis
    return analyze(parse_actions(w.document(), RelationTable(rules.tolerance)), rules).plan


def test_fig16_b_t_closure():
    plan = fig16_task()
    root = plan["operators"][plan["root"]]
    assert root["class"] == "BUILD"
    assert root["plot"] == ["$sequence", par("achieve03", "achieve02", "achieve01"),
                            ["$action", "achieve04"], ["$action", "achieve05"]]
    assert plan["operators"]["achieve04"]["next"] == ["achieve05"]
    assert sorted(plan["operators"]["achieve01"]["next"]) == ["achieve04"]
