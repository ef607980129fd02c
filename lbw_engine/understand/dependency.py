"""Step 2 of plan analysis (Sec. VI-C2): dependency closures build the upper levels.

Relations between two operators OPᵢ (earlier) and OPⱼ (later):

* B-T: base(OPᵢ) ∩ target(OPⱼ) ≠ ∅ — OPⱼ builds on what OPᵢ placed (ordered);
* B-S: base(OPᵢ) ∩ special(OPⱼ) ≠ ∅ — OPⱼ carries what OPᵢ placed (ordered);
* C-T: target(OPᵢ) ∩ target(OPⱼ) ≠ ∅ — several objects assembled on one common
  object (the paper's printed formula is garbled; this is what its text says):
  parallel.
* B-B: base(OPᵢ) ∩ base(OPⱼ) ≠ ∅ — OPⱼ moves again what OPᵢ moved (ordered). The
  paper's demonstrations move each object once; a cube put at A and then at B had
  both ACHIEVEs on the table in one C-T closure, in parallel, and the robot left it
  at A (helper round 10, v24a).
* S-S: OPⱼ puts an object where OPᵢ took another from (an SC⁻ and a later SC⁺
  relation of one frame, ``:wrt``, whose ``:at`` differ by less than analysis.yaml's
  ``same-spot`` in x and y; ordered). Blocks are at least 10 mm on a side, so two
  at rest that close share their spot. A cube put at A, then moved on, and a brick
  then put at A had the brick's ACHIEVE in parallel with the cube's first, and the
  robot found A taken (helper round 11, 93).

Passes search closures in the order of analysis.yaml (the paper: C-T, B-T, B-S,
B-T) and are repeated until nothing changes. A closure is a connected component
of one relation among the current top-level operators. It is grouped only over
stretches of the demonstration where no operator in between has an ordering
(B-T / B-S) dependency with it (docs/analysis.md, "Closures"): this keeps the
demonstrated order where the closure would otherwise jump over a dependent
operator, and reproduces Fig. 17. The group's plot layers its members by their
ordering dependencies: one layer is a ($parallel ...), several a ($sequence ...)
whose multi-member layers are inline ($parallel ...) (Fig. 16). Parallel members
are listed latest first, as the backward search of Fig. 16 meets them (Fig. 17,
Fig. 22).

Operators are indexed by object (base / target / special → operators), so each
pass is linear in the plan size; no pairwise scan of operators.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable

import networkx as nx

from lbw_engine.names import TABLE
from lbw_engine.rules.analysis import AnalysisRules
from lbw_engine.understand.state import Operator, make_operator


class _Index:
    """The current top-level operators, ordered by time, indexed by object and role."""

    def __init__(self, ops: list[Operator], same_spot: float = 0.0) -> None:
        self.ops = sorted(ops, key=lambda o: o.lo)
        self.los = [o.lo for o in self.ops]
        self.pos = {id(o): k for k, o in enumerate(self.ops)}
        self.by_role: dict[str, dict[str, list[Operator]]] = {
            role: defaultdict(list) for role in ("base", "target", "special")
        }
        for op in self.ops:
            for role, objs in (("base", op.base), ("target", op.target),
                               ("special", op.special)):
                for obj in objs:
                    self.by_role[role][obj].append(op)
        self.order = self._ordering_edges(same_spot)
        self.neighbours: dict[int, set[int]] = defaultdict(set)
        self.preds: dict[int, list[int]] = defaultdict(list)
        for i, j in self.order:
            self.neighbours[i].add(j)
            self.neighbours[j].add(i)
            self.preds[j].append(i)

    def edges(self, kind: str, among: set[int] | None = None) -> list[tuple[int, int]]:
        """Pairs of positions related by ``kind`` (B-T/B-S: earlier first), within ``among``."""
        def keep(op: Operator) -> bool:
            return among is None or self.pos[id(op)] in among

        out = []
        if kind == "C-T":
            sharers = self.by_role["target"]
            if among is not None:
                sharers = defaultdict(list)
                for p in sorted(among):
                    for obj in self.ops[p].target:
                        sharers[obj].append(self.ops[p])
            for sharing in sharers.values():
                # A chain over the sharers connects them all without n² pairs.
                out.extend((self.pos[id(a)], self.pos[id(b)])
                           for a, b in zip(sharing, sharing[1:], strict=False))
            return out
        role = {"B-T": "target", "B-S": "special", "B-B": "base"}[kind]
        later_ops = self.ops if among is None else [self.ops[p] for p in sorted(among)]
        for j_op in later_ops:
            for obj in getattr(j_op, role):
                for i_op in self.by_role["base"].get(obj, ()):
                    if i_op is not j_op and i_op.lo < j_op.lo and keep(i_op):
                        out.append((self.pos[id(i_op)], self.pos[id(j_op)]))
        return out

    def _ordering_edges(self, same_spot: float) -> set[tuple[int, int]]:
        """All ordered dependencies (B-T ∪ B-S ∪ B-B ∪ S-S) as (earlier, later) positions."""
        return set(self.edges("B-T")) | set(self.edges("B-S")) | set(self.edges("B-B")) | \
            self._same_spot_edges(same_spot)

    def _same_spot_edges(self, mm: float) -> set[tuple[int, int]]:
        """S-S: (i, j) where OPⱼ puts an object within ``mm`` of where OPᵢ, earlier, took
        another from. Left spots are kept in a grid of ``mm`` cells, so a place looks
        only at the 9 cells around it."""
        out: set[tuple[int, int]] = set()
        if mm <= 0:
            return out
        left: dict[tuple, list[tuple[int, str, tuple[float, ...]]]] = defaultdict(list)

        def cell(wrt: str | None, at: tuple[float, ...]) -> tuple:
            # x and y only: :at's z is a centre height, half a block's height apart for
            # blocks of other heights on one spot (a brick where a cube stood)
            return (wrt or TABLE, *(int(c // mm) for c in at[:2]))

        for j, op in enumerate(self.ops):
            for r in op.sc_plus:
                if r.at is None:
                    continue
                c = cell(r.wrt, r.at)
                for d in _NEAR_CELLS:
                    key = (c[0], *(a + b for a, b in zip(c[1:], d, strict=True)))
                    out.update((i, j) for i, subject, at in left.get(key, ())
                               if subject != r.subject and all(
                                   abs(a - b) < mm for a, b in zip(at[:2], r.at[:2], strict=True)))
            for r in op.sc_minus:
                if r.at is not None:
                    left[cell(r.wrt, r.at)].append((j, r.subject, r.at))
        return out

    def runs(self, members: list[int]) -> list[list[int]]:
        """Split a closure where an operator in between depends on the stretch."""
        members = sorted(members)
        out: list[list[int]] = [[members[0]]]
        current = set(out[0])
        for prev, nxt in zip(members, members[1:], strict=False):
            stretch = current | {nxt}
            blocked = any(self.neighbours.get(x, set()) & stretch for x in range(prev + 1, nxt))
            if blocked:
                out.append([nxt])
                current = {nxt}
            else:
                out[-1].append(nxt)
                current.add(nxt)
        return out


_NEAR_CELLS = [(a, b) for a in (-1, 0, 1) for b in (-1, 0, 1)]


def _components(nodes: Iterable[int], edges: Iterable[tuple[int, int]]) -> list[list[int]]:
    """Connected components (size ≥ 2) of an undirected graph, in time order."""
    graph = nx.Graph()
    graph.add_nodes_from(nodes)
    graph.add_edges_from(edges)
    comps = [sorted(c) for c in nx.connected_components(graph) if len(c) > 1]
    return sorted(comps)


def layered_plot(members: list[Operator], index: _Index) -> tuple:
    """The plot of a group: longest-path layers of its ordering dependencies."""
    ids = {index.pos[id(m)]: m for m in members}
    layer: dict[int, int] = {}
    for p in sorted(ids):  # time order is a topological order: edges go forward
        layer[p] = max((layer[i] + 1 for i in index.preds.get(p, ()) if i in ids), default=0)
    layers: list[list[Operator]] = [[] for _ in range(max(layer.values()) + 1)]
    for p in sorted(ids):
        layers[layer[p]].append(ids[p])
    items = [ly[0] if len(ly) == 1 else ("$parallel", *reversed(ly)) for ly in layers]
    if len(items) == 1:
        only = items[0]
        return only if isinstance(only, tuple) else ("$parallel", only)
    return ("$sequence", *items)


class Planner:
    """Runs the closure passes over the ACHIEVE operators of Step 1."""

    def __init__(self, rules: AnalysisRules) -> None:
        self.rules = rules
        self.created: list[Operator] = []  # in creation order, for naming

    def _new(self, cls: str, plot, members: list[Operator]) -> Operator:
        op = make_operator(cls, plot, members, self.rules.agents, self.rules.fixed)
        self.created.append(op)
        return op

    def protect(self, ops: list[Operator]) -> list[Operator]:
        """Wrap every operator with protected relations (SP ≠ ∅) in a PACHIEVE (Fig. 14)."""
        return [self._new(self.rules.protected_class, op, [op]) if op.sp else op for op in ops]

    def run_pass(self, kind: str, ops: list[Operator]) -> tuple[list[Operator], bool]:
        """Group every closure of ``kind``; return the new top level and whether it changed."""
        index = _Index(ops, self.rules.same_spot)
        kind_edges = index.edges(kind)
        groups: list[list[int]] = []
        for comp in _components(range(len(index.ops)), kind_edges):
            for run in index.runs(comp):
                if len(run) > 1:
                    groups.extend(_components(run, index.edges(kind, set(run))))
        if not groups:
            return index.ops, False
        grouped: set[int] = set()
        out: list[Operator] = []
        for group in sorted(groups):
            members = [index.ops[p] for p in group]
            plot = layered_plot(members, index)
            out.append(self._new(self.rules.closure_class, plot, members))
            grouped.update(group)
        out.extend(op for p, op in enumerate(index.ops) if p not in grouped)
        return sorted(out, key=lambda o: o.lo), True

    def root(self, ops: list[Operator]) -> Operator:
        """Run the passes to a fixed point and return the single root operator."""
        current = self.protect(ops)
        while len(current) > 1:
            changed = False
            for kind in self.rules.passes:
                current, step = self.run_pass(kind, current)
                changed = changed or step
                if len(current) == 1:
                    break
            if not changed:
                break
        if len(current) > 1:
            # Unrelated structures: one root over them, still honouring any order.
            index = _Index(current, self.rules.same_spot)
            current = [self._new(self.rules.closure_class,
                                 layered_plot(index.ops, index), index.ops)]
        top = current[0]
        if top.cls != self.rules.closure_class:
            # A task is always a BUILD at the top (Table V: Task → BUILD).
            top = self._new(self.rules.closure_class, top, [top])
        return top

