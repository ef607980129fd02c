"""The symbolic problem in unified-planning: PDDL domain and problem (PDDLWriter).

Every operation of rules/domain.yaml becomes one PDDL action per length of its
list parameters that the problem needs (PDDL has no lists: an object on four
supports is placed by the four-support variant). In a variant, an atom of a
*static* predicate (one no operation changes, like ``site``) over a list
becomes one fact that lists the elements in order (``site-4 ?place ?s1 .. ?s4``,
written into the initial state for every place on four supports): the
supports are then the place's own, each once. A removal with ``*``
(effects.yaml's "whatever it rested on") deletes the preconditions it matches,
which name the supports. domain.yaml's ``planner-pre`` are preconditions here.
The same model, with tasks and methods added, is written as HDDL (hddl.py).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path

import unified_planning.shortcuts as up
from unified_planning.io import PDDLWriter

from lbw_engine.export.problem import SymbolicProblem
from lbw_engine.rules.domain import OperationDomain
from lbw_engine.understand.domain import Fact, ground, matches

up.get_environment().credits_stream = None  # the planners' credit banners are not our output


@dataclass(frozen=True)
class Variant:
    """One PDDL action: an operation with a length for each list parameter."""

    name: str
    operation: str
    sizes: dict[str, int]  # list parameter -> number of elements
    params: tuple[tuple[str, str], ...]  # (PDDL parameter, domain parameter)

    def bindings(self, args: list[str], op: OperationDomain) -> dict:
        """Domain bindings from the PDDL action's arguments (lists regrouped)."""
        out: dict = {}
        for (_, dom), value in zip(self.params, args, strict=True):
            if op.params[dom].many:
                out[dom] = (*out.get(dom, ()), value)
            else:
                out[dom] = value
        return out

    def arguments(self, bindings: dict) -> list[str]:
        """The PDDL action's arguments for domain bindings."""
        out, used = [], {}
        for _, dom in self.params:
            value = bindings[dom]
            if isinstance(value, tuple):
                used[dom] = used.get(dom, -1) + 1
                value = value[used[dom]]
            out.append(value)
        return out


@dataclass
class Model:
    """A unified-planning problem built from a symbolic problem, and its action variants."""

    problem: up.Problem
    variants: dict[str, Variant] = field(default_factory=dict)
    types: dict[str, up.Type] = field(default_factory=dict)
    fluents: dict[str, up.Fluent] = field(default_factory=dict)
    objects: dict[str, up.Object] = field(default_factory=dict)
    listed: dict[str, tuple[str, int]] = field(default_factory=dict)  # listing form -> (pred, k)
    listed_at: dict[str, int] = field(default_factory=dict)  # static pred -> its list position

    def variant_for(self, operation: str, bindings: dict) -> Variant:
        """The variant of ``operation`` that fits these bindings' list lengths."""
        sizes = {k: len(v) for k, v in bindings.items() if isinstance(v, tuple)}
        return next(v for v in self.variants.values()
                    if v.operation == operation and v.sizes == sizes)


def build_model(sp: SymbolicProblem, name: str, hierarchical: bool = False) -> Model:
    """The UP problem (a HierarchicalProblem for HDDL) of ``sp``, with its init and goal.

    The hierarchy is what was demonstrated (a PACHIEVE lifts a loaded object,
    Fig. 14), so a hierarchical problem leaves out domain.yaml's ``planner-pre``.
    """
    from unified_planning.model.htn import HierarchicalProblem

    problem = HierarchicalProblem(name) if hierarchical else up.Problem(name)
    model = Model(problem)
    _types(model, sp)
    for pred, kinds in sp.domain.predicates.items():
        args = {f"a{i}": model.types[k] for i, k in enumerate(kinds, 1)}
        model.fluents[pred] = up.Fluent(pred, up.BoolType(), **args)
        problem.add_fluent(model.fluents[pred], default_initial_value=False)
    kinds = {**sp.objects, **{p: sp.domain.place_type for p in sp.places}}
    for obj, kind in kinds.items():
        model.objects[obj] = up.Object(obj, model.types[kind])
        problem.add_object(model.objects[obj])
    sizes = sorted({1} | {len(p.supports) for p in sp.places.values()})
    statics = _statics(sp)
    for op in sp.domain.operations.values():
        for variant, action in _variants(model, op, sizes, statics, not hierarchical):
            model.variants[variant.name] = variant
            problem.add_action(action)
    for fact in sorted(sp.init | _listed(model, statics, sp.init)):
        problem.set_initial_value(fluent(model, fact), True)
    if not hierarchical:
        for fact in sorted(sp.goal):
            problem.add_goal(fluent(model, fact))
    return model


def fluent(model: Model, fact: Fact):
    """A ground fact as a UP expression."""
    return model.fluents[fact[0]](*(model.objects[a] for a in fact[1:]))


def write(model: Model, domain_file: Path, problem_file: Path) -> None:
    """Write the domain and problem files (PDDL, or HDDL for a hierarchical problem)."""
    writer = PDDLWriter(model.problem)
    domain_file.write_text(writer.get_domain(), encoding="utf-8")
    problem_file.write_text(writer.get_problem(), encoding="utf-8")


def _types(model: Model, sp: SymbolicProblem) -> None:
    """UP user types in parent-first order."""
    todo = dict(sp.domain.types)
    while todo:
        for kind, parent in list(todo.items()):
            if parent is None or parent in model.types:
                model.types[kind] = up.UserType(kind, model.types.get(parent))
                del todo[kind]


def _statics(sp: SymbolicProblem) -> set[str]:
    """Predicates no operation adds or removes."""
    changed = {a.pred for op in sp.domain.operations.values() for a in (*op.add, *op.remove)}
    return set(sp.domain.predicates) - changed


def _listed_name(model: Model, pred: str, size: int) -> str:
    """The name of a static predicate's form that lists ``size`` elements; declared on first use."""
    name = f"{pred}-{size}"
    while name in model.fluents and name not in model.listed:
        name += "-"
    if name not in model.fluents:
        base = model.fluents[pred]
        kinds = [p.type for p in base.signature]
        at = model.listed_at[pred]
        kinds[at:at + 1] = [kinds[at]] * size
        model.fluents[name] = up.Fluent(name, up.BoolType(),
                                        **{f"a{i}": k for i, k in enumerate(kinds, 1)})
        model.problem.add_fluent(model.fluents[name], default_initial_value=False)
        model.listed[name] = (pred, size)
    return name


def _listed(model: Model, statics: set[str], init) -> set[Fact]:
    """Initial facts of the listing forms: the elements that share the other arguments."""
    out: set[Fact] = set()
    for name, (pred, size) in model.listed.items():
        at = model.listed_at[pred] + 1
        groups: dict[tuple, list[str]] = {}
        for f in init:
            if f[0] == pred:
                groups.setdefault(f[:at] + f[at + 1:], []).append(f[at])
        for key, items in groups.items():
            if len(items) == size:
                out.add((name, *key[1:at], *sorted(items), *key[at:]))
    return out


def _variants(model: Model, op: OperationDomain, sizes: list[int], statics: set[str],
              planner: bool):
    """(Variant, UP action) for each combination of list lengths of ``op``."""
    lists = [p for p in op.params.values() if p.many]
    for combo in itertools.product(sizes, repeat=len(lists)):
        size = dict(zip((p.name for p in lists), combo, strict=True))
        params: list[tuple[str, str]] = []
        tokens: dict = {}
        for p in op.params.values():
            names = [p.name] if not p.many or size[p.name] == 1 else \
                [f"{p.name}{i}" for i in range(1, size[p.name] + 1)]
            params += [(n, p.name) for n in names]
            tokens[p.name] = tuple(names) if p.many else names[0]
        suffix = "-".join(str(size[p.name]) for p in lists if size[p.name] > 1)
        name = op.name.lower() + (f"-{suffix}" if suffix else "")
        kinds = {n: model.types[op.params[d].type] for n, d in params}
        action = up.InstantaneousAction(name, **kinds)
        yield Variant(name, op.name, size, tuple(params)), \
            _fill(model, op, action, tokens, statics, planner)


def _fill(model: Model, op: OperationDomain, action, tokens: dict, statics: set[str],
          planner: bool):
    """Preconditions and effects of one variant (parameters stand in for names)."""
    def expr(fact: Fact):
        return model.fluents[fact[0]](*(action.parameter(a) for a in fact[1:]))

    pre = [f for atom in (*op.pre, *(op.planner_pre if planner else ()))
           for f in _static_listed(model, atom, tokens, statics) or ground(atom, tokens)]
    add = [f for atom in op.add for f in ground(atom, tokens)]
    gone: list[Fact] = []
    for atom in op.remove:
        for pattern in ground(atom, tokens):
            gone += [f for f in pre if matches(pattern, f)] if "*" in pattern else [pattern]
    for fact in dict.fromkeys(pre):
        action.add_precondition(expr(fact))
    for fact in dict.fromkeys(gone):
        if fact not in add:
            action.add_effect(expr(fact), False)
    for fact in dict.fromkeys(add):
        action.add_effect(expr(fact), True)
    return action


def _static_listed(model: Model, atom, tokens: dict, statics: set[str]) -> list[Fact]:
    """A static atom over a list of several: its one listing fact ([] otherwise)."""
    lists = [i for i, a in enumerate(atom.args) if isinstance(tokens.get(a[1:]), tuple)
             and len(tokens[a[1:]]) > 1]
    if atom.pred not in statics or len(lists) != 1:
        return []
    at = lists[0]
    model.listed_at.setdefault(atom.pred, at)
    if model.listed_at[atom.pred] != at:
        return []
    items = tokens[atom.args[at][1:]]
    name = _listed_name(model, atom.pred, len(items))
    others = [tokens[a[1:]] for a in atom.args]
    return [(name, *others[:at], *items, *others[at + 1:])]
