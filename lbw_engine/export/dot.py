"""The learned plan as a Graphviz picture (DOT text, written with the graphviz package).

Operators are boxes (class, base, target as in Fig. 13 / 22), recognized
operations ellipses. A ``$sequence`` numbers its edges in order; a
``$parallel`` goes through a small "parallel" node (the arc of Fig. 17).
Only text is written: rendering needs Graphviz's ``dot``, which lbw does not.
"""

from __future__ import annotations

from typing import Any

import graphviz

from lbw_engine.do.plan import Plan


def plan_dot(plan: Plan) -> str:
    """DOT source of ``plan``."""
    g = graphviz.Digraph(plan.root, graph_attr={"rankdir": "TB"},
                         node_attr={"fontname": "Helvetica", "fontsize": "10"})
    for name, op in plan.operators.items():
        label = f"{name}\\n{op.cls}"
        for slot in ("base", "target"):
            if op.slots.get(slot):
                label += f"\\n{slot}: {' '.join(op.slots[slot])}"
        g.node(name, label, shape="box", style="rounded")
    for name, op in plan.operators.items():
        _plot(g, plan, name, op.plot, [0])
    return g.source


def _plot(g: graphviz.Digraph, plan: Plan, parent: str, plot: Any, counter: list[int],
          order: str | None = None) -> None:
    """Edges from ``parent`` to the plot's items."""
    if plot[0] == "$action":
        child = plot[1]
        if child not in plan.operators:
            g.node(child, f"{child}\\n{plan.leaf_operations[child]}", shape="ellipse")
        g.edge(parent, child, label=order or "")
        return
    if plot[0] == "$parallel":
        counter[0] += 1
        hub = f"{parent}-parallel-{counter[0]}"
        g.node(hub, "parallel", shape="diamond", fontsize="8")
        g.edge(parent, hub, label=order or "")
        for item in plot[1:]:
            _plot(g, plan, hub, item, counter)
        return
    for i, item in enumerate(plot[1:], 1):
        _plot(g, plan, parent, item, counter, str(i))
