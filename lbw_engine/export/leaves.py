"""The learned plan's leaves as ground operations of rules/domain.yaml.

The plan is walked depth first in plot order (as the tracer walks it,
Sec. VII-A). Each leaf's parameters are bound by type, from its operator:

1. a parameter whose type has exactly one object in the problem (the hand,
   the table) gets it;
2. the first other single parameter that fits the operator's focus object
   (commands.yaml ``focus``) gets it;
3. the rest are found in the symbolic state (``find_bindings``: where a picked
   object rests);
4. what is still open comes from the operator's placement (its SC⁺ support
   relation for the focus): the place, and the support(s).

Each leaf must then meet its preconditions in the state the leaves before it
left; a leaf that does not is an error naming it.
"""

from __future__ import annotations

from dataclasses import dataclass

from lbw_engine.do.plan import Operator, Plan, Relation
from lbw_engine.errors import InputError
from lbw_engine.export.problem import Place, SymbolicProblem
from lbw_engine.rules.commands import CommandRules
from lbw_engine.rules.domain import OperationDomain
from lbw_engine.understand.domain import State, apply, as_bindings, check, find_bindings, ground


@dataclass(frozen=True)
class Step:
    """A plan leaf as a ground operation."""

    leaf: str
    operator: str
    operation: str
    bindings: dict[str, str | tuple[str, ...]]


def bind_leaves(plan: Plan, problem: SymbolicProblem, commands: CommandRules) -> list[Step]:
    """Every leaf of ``plan`` in execution order, bound and checked from the initial state."""
    walker = _Walker(plan, problem, commands)
    walker.operator(plan.root)
    return walker.steps


class _Walker:
    """Depth-first walk that carries the symbolic state along."""

    def __init__(self, plan: Plan, problem: SymbolicProblem, commands: CommandRules) -> None:
        self.plan, self.problem, self.commands = plan, problem, commands
        self.state: State = problem.init
        self.steps: list[Step] = []

    def operator(self, name: str) -> None:
        """Walk one operator's plot."""
        self.plot(self.plan.operators[name], self.plan.operators[name].plot)

    def plot(self, op: Operator, plot: list) -> None:
        """Walk a plot of ``op``: operators recurse, leaves are bound and applied."""
        if plot[0] != "$action":
            for sub in plot[1:]:
                self.plot(op, sub)
        elif plot[1] in self.plan.operators:
            self.operator(plot[1])
        else:
            self.leaf(op, plot[1])

    def leaf(self, op: Operator, leaf: str) -> None:
        """Bind, check and apply one leaf."""
        operation = self.commands.operation_of(self.plan.leaf_operations[leaf])
        where = f"operators.{op.name}.plot: {leaf}"
        dom = self.problem.domain.operations.get(operation)
        if dom is None:
            raise InputError(f"operation {operation} is not in {self.problem.domain.file}",
                             file=self.plan.file, where=where)
        bindings = self._bind(dom, op)
        unmet = check(self.state, dom, bindings) if set(bindings) == set(dom.params) else None
        if unmet is None or unmet:
            missing = "unbound parameters" if unmet is None else \
                "; ".join(" ".join(f) for f in unmet)
            raise InputError(f"{operation} does not fit {self.problem.domain.file} here: "
                             f"{missing}", file=self.plan.file, where=where)
        self.state = apply(self.state, dom, bindings)
        self.steps.append(Step(leaf, op.name, operation, bindings))

    def _bind(self, dom: OperationDomain, op: Operator) -> dict:
        """Steps 1-4 of the module docstring."""
        out: dict = {}
        focus = focus_object(op, self.commands, self.problem)
        for p in dom.params.values():
            objs = self.problem.of_type(p.type)
            if not p.many and len(objs) == 1:
                out[p.name] = objs[0]
        for p in dom.params.values():
            if p.name not in out and not p.many and focus in self.problem.of_type(p.type):
                out[p.name] = focus
                break
        out = find_bindings(self.state, dom, out)
        place = self._placement(op, focus)
        for p in dom.params.values():
            if p.name in out or place is None:
                continue
            if p.type == self.problem.domain.place_type:
                out[p.name] = place.name
            elif p.many or len(place.supports) == 1:
                out[p.name] = place.supports if p.many else place.supports[0]
        return as_bindings(dom, out)

    def _placement(self, op: Operator, focus: str | None) -> Place | None:
        """The place the operator puts its focus object (a new one if the root never named it)."""
        support = self.problem.domain.support_relations
        rel = next((r for r in op.sc_plus if r.subject == focus and r.type in support), None)
        if rel is None:
            return None
        for place in self.problem.places.values():
            if any(_same(rel, r) for r in place.relations):
                return place
        place, sites = add_place(self.problem, rel, op.name)
        self.state = self.state | sites
        return place


def add_place(problem: SymbolicProblem, rel: Relation, family: str) -> tuple[Place, State]:
    """A place for a relation the root does not name (an object moved twice), with its sites."""
    name = f"{rel.subject}-{family}"
    while name in problem.objects or name in problem.places:
        name += "-"
    place = Place(name, rel.subject, rel.objects, [rel])
    problem.places[name] = place
    rows = [{"place": name, "support": s, "owner": rel.subject} for s in rel.objects]
    sites = frozenset(f for each, atom in problem.domain.initial if each in ("site", "owner")
                      for b in rows for f in ground(atom, b))
    problem.init = problem.init | sites
    return place, sites


def focus_object(op: Operator, commands: CommandRules, problem: SymbolicProblem) -> str | None:
    """The object an operator moves or touches (commands.yaml ``focus``)."""
    movable = set(problem.of_type(problem.domain.kinds["movable"]))
    for rels in (op.sc_plus, op.sc_minus):
        for r in rels:
            if r.type in commands.focus_relations and r.subject in movable:
                return r.subject
    for slot in commands.focus_slots:
        for name in op.slots[slot]:
            if name in movable:
                return name
    return None


def _same(a: Relation, b: Relation) -> bool:
    """The same taught relation (type, subject, supports, position and frame)."""
    return (a.type, a.subject, set(a.objects), a.at, a.wrt) == \
        (b.type, b.subject, set(b.objects), b.at, b.wrt)
