"""The learned plan as an HTN (HDDL) through unified-planning's HierarchicalProblem.

Every operator of the plan (BUILD, PACHIEVE, ACHIEVE, FETCH, PUT, FAKE; Fig. 13,
14, 17) becomes a task with one method; the method's subtasks are the plot's
items: operators as their tasks, recognized operations as the ground actions of
the exported domain (their arguments found by leaves.py). ``$sequence`` orders
its items; the items of a ``$parallel`` are unordered among themselves (Fig. 17:
the arc). The problem's task network is the root's task. unified-planning 1.3
writes HDDL with its PDDLWriter when the problem is hierarchical.
"""

from __future__ import annotations

from typing import Any

from unified_planning.model.htn import Method, Subtask, Task

from lbw_engine.do.plan import Plan
from lbw_engine.export.leaves import Step
from lbw_engine.export.pddl import Model


def add_hierarchy(model: Model, plan: Plan, steps: list[Step]) -> None:
    """Tasks and methods for every operator of ``plan``; the root as the initial task."""
    problem = model.problem
    tasks = {name: Task(name) for name in plan.operators}
    for task in tasks.values():
        problem.add_task(task)
    by_leaf = {s.leaf: s for s in steps}
    for name, op in plan.operators.items():
        method = Method(f"m-{name}")
        method.set_task(tasks[name])
        _network(method, op.plot, tasks, by_leaf, model)
        problem.add_method(method)
    problem.task_network.add_subtask(tasks[plan.root])


def _network(method: Method, plot: Any, tasks: dict[str, Task], steps: dict[str, Step],
             model: Model) -> list[Subtask]:
    """Add a plot's subtasks to ``method``; return the first and last groups' subtasks.

    Returns every subtask the plot added (so a parent ``$sequence`` can order
    whole groups before one another).
    """
    if plot[0] == "$action":
        name = plot[1]
        if name in tasks:
            sub = Subtask(tasks[name])
        else:
            step = steps[name]
            variant = model.variant_for(step.operation, step.bindings)
            action = model.problem.action(variant.name)
            sub = Subtask(action, *(model.objects[a] for a in variant.arguments(step.bindings)))
        method.add_subtask(sub)
        return [sub]
    groups = [_network(method, item, tasks, steps, model) for item in plot[1:]]
    if plot[0] == "$sequence":
        for before, after in zip(groups, groups[1:], strict=False):
            for a in before:
                for b in after:
                    method.set_ordered(a, b)
    return [s for g in groups for s in g]
