"""plan.txt (rules/plot.lark): round trip plan.json → plan.txt → parsed, and the paper's text."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.bench_analysis import synthetic_task
from lbw_engine.errors import InputError
from lbw_engine.rules import load_rules
from lbw_engine.understand import (
    RelationTable,
    analyze,
    analyze_file,
    parse_actions,
    read_plan_text,
    write_plan_text,
)

DATA = Path(__file__).resolve().parent.parent / "data"


def _synthetic(n):
    rules = load_rules().analysis
    return analyze(parse_actions(synthetic_task(n), RelationTable(rules.tolerance)), rules).plan


PLANS = {
    "Fig12-inverted-arch": lambda: analyze_file(DATA / "fig12-inverted-arch.actions.json").plan,
    "Fig20-build-table": lambda: analyze_file(DATA / "fig20-build-table.actions.json").plan,
    "synthetic-40": lambda: _synthetic(40),
}


@pytest.mark.parametrize("make", PLANS.values(), ids=PLANS.keys())
def test_round_trip(make):
    plan = make()
    text = write_plan_text(plan)
    assert read_plan_text(text) == plan
    assert text.index(f"($action {plan['root']}") < text.index("($action", text.index(
        f"($action {plan['root']}") + 1)


FIG22_TEXT = """
;;; Top level (Expansion level 0)
($action build5197
  :base (plate189 brick186 brick188 brick187 brick190)
  :target (table182)
 :special nil
  :next-action nil
  :plot ($sequence ($action build5164) ($action achieve4824)))
;;; Expansion level 1
($action build5164
  :base (brick190 brick187 brick188 brick186)
  :target (table182)
  :special nil
  :next-action (achieve4824)
  :plot ($parallel ($action achieve4748) ($action achieve4679)
   ($action achieve4610) ($action achieve4541)))
($action achieve4824
  :base (plate189)
  :target (brick188 brick187 brick186 brick190)
  :special nil
  :next-action nil
  :plot ($sequence ($action fetch4773) ($action put4812)))
"""


def test_reads_fig22_as_printed():
    plan = read_plan_text(FIG22_TEXT)
    assert plan["root"] == "build5197"
    assert [op["class"] for op in plan["operators"].values()] == ["BUILD", "BUILD", "ACHIEVE"]
    assert plan["operators"]["build5164"]["next"] == ["achieve4824"]
    assert plan["operators"]["build5164"]["plot"][0] == "$parallel"
    assert len(plan["operators"]["build5164"]["plot"]) == 5


def test_reads_fig14_relations():
    text = """($action pachieve01 :base (planar-brick2) :target (short-brick1)
      :sc-plus ((planar-brick2 on short-brick1 :at #f(-16.0 1.8 37.7) :wrt short-brick1))
      :sp ((medium-brick4 on planar-brick2 :at #f(34.3 -42.4 42.7) :wrt planar-brick2))
      :plot ($action achieve04))"""
    op = read_plan_text(text)["operators"]["pachieve01"]
    assert op["class"] == "PACHIEVE"
    assert op["sc_plus"] == [["on", "planar-brick2", "short-brick1",
                              {"at": [-16.0, 1.8, 37.7], "wrt": "short-brick1"}]]
    assert op["sp"][0][3]["at"] == [34.3, -42.4, 42.7]


BAD_TEXT = [
    ("unbalanced", "($action build01 :plot ($action a)", "not in the plot notation", 1),
    ("unknown-slot", "($action build01\n :colour red :plot ($action a))",
     "not in the plot notation", 2),
    ("no-plot", "($action build01 :base nil)", "has no :plot", None),
    ("twice", "($action build01 :plot ($action a))\n($action build01 :plot ($action a))",
     "written twice", None),
    ("no-class", "($action thing7 :plot ($action a))", "no :class", None),
]


@pytest.mark.parametrize("text,fragment,line", [b[1:] for b in BAD_TEXT],
                         ids=[b[0] for b in BAD_TEXT])
def test_bad_plan_text(text, fragment, line):
    with pytest.raises(InputError) as info:
        read_plan_text(text, file="plan.txt")
    assert fragment in info.value.message and info.value.file == "plan.txt"
    if line:
        assert info.value.line == line
