"""The analysis pipeline and the plan.json form (design.md "Plan").

actions.json → Step 1 templates (Fig. 15) → PACHIEVE wrapping and dependency
closures (Sec. VI-C2) → named operators → plan.json. Conventions (see
docs/analysis.md): operators are named like the paper, class in lower case plus
a per-class counter (achieve01, fetch02, pachieve01, build03); template
operators are numbered in demonstration order, upper operators in the order the
closure passes create them. Plot leaves are the recognized operations' names
(["$action", "reach01"]). ``next`` lists the operators that immediately follow
an operator inside its parent's $sequence (none inside a $parallel).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.guard import shorten
from lbw_engine.rules import load_rules
from lbw_engine.rules.analysis import AnalysisRules
from lbw_engine.understand.actions import ActionSequence, Operation, load_actions
from lbw_engine.understand.dependency import Planner
from lbw_engine.understand.gcpause import without_gc
from lbw_engine.understand.relations import RelationTable, sorted_json
from lbw_engine.understand.state import Member, Operator
from lbw_engine.understand.templates import build_step1, parse_sequence


@dataclass
class Analysis:
    """The result of analysing one action sequence."""

    root: Operator
    operators: dict[str, Operator]  # by name, breadth first from the root
    achieves: list[Operator]  # the top-level operators of Step 1, in order
    removed: list[Operation]  # redundant operations left out of the plan
    plan: dict[str, Any]  # the plan.json document


@without_gc
def analyze_file(actions_path: str | Path, rules_dir: str | Path | None = None) -> Analysis:
    """Load rules and an actions.json file and analyse it.

    The file must end with the hand empty, as the recognizer's rules define
    holding (effects.yaml ``roles: hold``).
    """
    ruleset = load_rules(rules_dir)
    rules = ruleset.analysis
    seq = load_actions(actions_path, RelationTable(rules.tolerance), ruleset.hold_relation)
    return analyze(seq, rules)


def split_trailing(
    seq: ActionSequence, trailing: frozenset[str]
) -> tuple[ActionSequence, list[Operation]]:
    """Cut off the run of ``trailing`` operations that ends the demonstration.

    Fig. 12 ends "withdraw01 withdraw02": the hand leaving after the last PUT.
    Fig. 17 has no trace of them, so they are redundant (analysis.yaml
    templates.trailing); inside the task the templates' WITHDRAW* still apply.
    """
    ops = seq.operations
    cut = len(ops)
    while cut > 0 and ops[cut - 1].operation in trailing:
        cut -= 1
    if cut == len(ops) or cut == 0:
        return seq, []
    return replace(seq, operations=ops[:cut]), list(ops[cut:])


@without_gc
def analyze(seq: ActionSequence, rules: AnalysisRules) -> Analysis:
    """Plan analysis of Sec. VI on a loaded action sequence."""
    tpl = rules.templates()
    seq, tail = split_trailing(seq, rules.trailing)
    tree = parse_sequence(tpl, seq)
    achieves, removed = build_step1(tree, seq, rules)
    removed = [*removed, *tail]
    if not achieves:
        names = " ".join(op.name for op in removed)
        raise InputError(f"no template of {tpl.file.name} makes an operator from the "
                         f"sequence; all of it is redundant ({names})",
                         file=seq.file, where="operations")
    planner = Planner(rules)
    root = planner.root(achieves)
    ordered = _breadth_first(root)
    _name(ordered, planner.created, seq)
    _link_next(ordered)
    operators = {op.name: op for op in ordered}
    plan = {"root": root.name, "operators": {n: operator_json(op) for n, op in operators.items()}}
    return Analysis(root, operators, achieves, removed, plan)


def _plot_members(plot: Any) -> list[Member]:
    """Members of a plot in listed order."""
    if isinstance(plot, tuple):
        return [m for item in plot[1:] for m in _plot_members(item)]
    return [plot]


def _breadth_first(root: Operator) -> list[Operator]:
    """All operators under ``root``, level by level (the order of Fig. 22)."""
    out, frontier = [], [root]
    while frontier:
        out.extend(frontier)
        frontier = [m for op in frontier for m in _plot_members(op.plot)
                    if isinstance(m, Operator)]
    return out


def _name(ordered: list[Operator], created: list[Operator], seq: ActionSequence) -> None:
    """Name operators: template ones by demonstration order, then upper ones by creation."""
    created_ids = {id(op): k for k, op in enumerate(created)}
    template = sorted((op for op in ordered if id(op) not in created_ids),
                      key=lambda op: (op.lo, -op.hi))
    upper = sorted((op for op in ordered if id(op) in created_ids),
                   key=lambda op: created_ids[id(op)])
    counters: dict[str, int] = {}
    leaves = {op.name: op.index for op in seq.operations}
    for op in [*template, *upper]:
        counters[op.cls] = counters.get(op.cls, 0) + 1
        op.name = f"{op.cls.lower()}{counters[op.cls]:02d}"
        if op.name in leaves:
            raise InputError(f"the operation name {shorten(op.name)} is also the name of a plan "
                             "operator; rename the operation",
                             file=seq.file, where=f"operations[{leaves[op.name]}].name")


def _heads(item: Any) -> list[Member]:
    """The members that start a plot item."""
    if not isinstance(item, tuple):
        return [item]
    if item[0] == "$sequence":
        return _heads(item[1])
    return [m for sub in item[1:] for m in _heads(sub)]


def _tails(item: Any) -> list[Member]:
    """The members that end a plot item."""
    if not isinstance(item, tuple):
        return [item]
    if item[0] == "$sequence":
        return _tails(item[-1])
    return [m for sub in item[1:] for m in _tails(sub)]


def _link_next(ordered: list[Operator]) -> None:
    """Set ``next`` of every operator from the $sequence of its parent's plot."""

    def walk(item: Any) -> None:
        if not isinstance(item, tuple):
            return
        subs = item[1:]
        if item[0] == "$sequence":
            for a, b in zip(subs, subs[1:], strict=False):
                follow = _heads(b)
                for m in _tails(a):
                    if isinstance(m, Operator):
                        m.next = follow
        for sub in subs:
            walk(sub)

    for op in ordered:
        walk(op.plot)


def _name_of(member: Member) -> str:
    """An operator's or a recognized operation's name."""
    return member.name


def plot_json(plot: Any) -> list:
    """PLOT = ["$sequence", PLOT...] | ["$parallel", PLOT...] | ["$action", NAME]."""
    if isinstance(plot, tuple):
        return [plot[0], *(plot_json(p) for p in plot[1:])]
    return ["$action", _name_of(plot)]


def operator_json(op: Operator) -> dict[str, Any]:
    """One plan.json operator entry."""
    return {
        "class": op.cls,
        "base": sorted(op.base),
        "target": sorted(op.target),
        "special": sorted(op.special),
        "sc_plus": sorted_json(op.sc_plus),
        "sc_minus": sorted_json(op.sc_minus),
        "si": sorted_json(op.si),
        "sp": sorted_json(op.sp),
        "plot": plot_json(op.plot),
        "next": [_name_of(m) for m in op.next],
    }
