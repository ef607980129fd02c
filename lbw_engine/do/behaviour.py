"""A learned plan as a py_trees behaviour tree, defined as data (tree.yaml), and ticked.

The tree mirrors the plot (Fig. 17): a plan operator is a Sequence; ``$sequence``
is a Sequence, ``$parallel`` a Parallel; a recognized operation is a leaf that,
when ticked, finds its goal against the execution model as it is then and runs
its Table IX commands on the robot (Sec. VII-B); an operator that holds leaves
of its own ends with an update leaf that applies its SC⁻ / SC⁺ to the model
(Sec. VII-A 2c). Node kinds are a closed registry (``KINDS``).

The robot does one thing at a time, so a leaf runs to completion in the tick
that starts it and a Parallel's branches run in listed order; the plain path's
balance-aware order of ``$parallel`` branches (balance.py) is not applied here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import py_trees

from lbw_engine.do.expander import Expander
from lbw_engine.do.plan import Plan
from lbw_engine.do.tracing import Trace, TracedOp, trace_leaf
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.rules.commands import CommandRules

KINDS = ("sequence", "parallel", "action", "update")
Status = py_trees.common.Status


def tree_data(plan: Plan) -> dict[str, Any]:
    """The behaviour tree of ``plan`` as plain data (what tree.yaml holds)."""
    return {"plan": plan.root, "tree": _operator(plan, plan.root)}


def _operator(plan: Plan, name: str) -> dict[str, Any]:
    """An operator: a Sequence of its plot, then its update if it holds leaves."""
    op = plan.operators[name]
    children = [_plot(plan, name, op.plot)]
    if any(leaf not in plan.operators for leaf in _direct(op.plot)):
        children.append({"kind": "update", "name": f"{name} done", "operator": name})
    return {"kind": "sequence", "name": f"{name} ({op.cls})", "children": children}


def _plot(plan: Plan, owner: str, plot: list) -> dict[str, Any]:
    """A plot item: an operator, a leaf, or a Sequence / Parallel of items."""
    if plot[0] == "$action":
        if plot[1] in plan.operators:
            return _operator(plan, plot[1])
        return {"kind": "action", "name": plot[1], "operator": owner,
                "operation": plan.leaf_operations[plot[1]]}
    kind = "sequence" if plot[0] == "$sequence" else "parallel"
    return {"kind": kind, "name": plot[0],
            "children": [_plot(plan, owner, item) for item in plot[1:]]}


def _direct(plot: list) -> list[str]:
    """The $action names of a plot."""
    if plot[0] == "$action":
        return [plot[1]]
    return [n for item in plot[1:] for n in _direct(item)]


class Runner:
    """What the leaves act on: the plan, the execution model and the robot."""

    def __init__(self, plan: Plan, rules: CommandRules, model: EnvModel,
                 send: Callable[[list], Any]) -> None:
        self.plan, self.rules, self.model, self.send = plan, rules, model, send
        self.expander = Expander(rules, model)
        self.ops: list[TracedOp] = []
        self.failure: str | None = None

    def leaf(self, operator: str, leaf: str) -> None:
        """Trace one leaf against the current model and run its commands."""
        op = trace_leaf(self.plan, self.rules, self.model, self.expander,
                        self.plan.operators[operator], leaf)
        self.ops.append(op)
        self.send(op.commands)

    def update(self, operator: str) -> None:
        """An operator's SC⁻ / SC⁺ (Sec. VII-A 2c)."""
        op = self.plan.operators[operator]
        self.model.apply(op.sc_minus, op.sc_plus)


class _Leaf(py_trees.behaviour.Behaviour):
    """A leaf that calls the runner once and reports success or the failure."""

    def __init__(self, name: str, call: Callable[[], None], runner: Runner) -> None:
        super().__init__(name)
        self.call, self.runner = call, runner

    def update(self) -> Status:
        """Run the call; a task that cannot be done fails the tree."""
        try:
            self.call()
        except TaskFailed as exc:
            self.runner.failure = str(exc)
            return Status.FAILURE
        return Status.SUCCESS


def build(data: Any, runner: Runner, file: str = "<tree>") -> py_trees.behaviour.Behaviour:
    """The py_trees tree of tree data; bad data is an InputError naming the node."""
    if not isinstance(data, dict) or not isinstance(data.get("tree"), dict):
        raise InputError("a tree file is a mapping with 'plan' and 'tree'", file=file)
    return _node(data["tree"], runner, file, "tree")


def _node(node: dict, runner: Runner, file: str, where: str) -> py_trees.behaviour.Behaviour:
    """One node of the registry ``KINDS``."""
    kind = node.get("kind") if isinstance(node, dict) else None
    if kind not in KINDS:
        raise InputError(f"node kind {kind!r} is not one of {', '.join(KINDS)}",
                         file=file, where=where)
    name = str(node.get("name", kind))
    if kind in ("sequence", "parallel"):
        children = [_node(c, runner, file, f"{where}.children[{i}]")
                    for i, c in enumerate(node.get("children") or [])]
        if kind == "sequence":
            return py_trees.composites.Sequence(name, memory=True, children=children)
        policy = py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=True)
        return py_trees.composites.Parallel(name, policy=policy, children=children)
    operator = node.get("operator")
    if operator not in runner.plan.operators:
        raise InputError(f"operator {operator!r} is not in the plan", file=file, where=where)
    if kind == "update":
        return _Leaf(name, lambda: runner.update(operator), runner)
    if name not in runner.plan.leaf_operations:
        raise InputError(f"{name!r} is not a recognized operation of the plan",
                         file=file, where=where)
    return _Leaf(name, lambda: runner.leaf(operator, name), runner)


def run_tree(plan: Plan, rules: CommandRules, model: EnvModel, send: Callable[[list], Any],
             max_ticks: int = 1000) -> tuple[Trace, int]:
    """Build the plan's tree and tick it until it is done; the trace it made and the ticks.

    Raises TaskFailed when a leaf cannot be done.
    """
    runner = Runner(plan, rules, model, send)
    root = build(tree_data(plan), runner)
    ticks = 0
    while root.status in (Status.INVALID, Status.RUNNING) and ticks < max_ticks:
        root.tick_once()
        ticks += 1
    if root.status != Status.SUCCESS:
        raise TaskFailed(runner.failure or f"the behaviour tree ended {root.status.value}")
    return Trace(runner.ops, model), ticks
