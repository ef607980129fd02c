"""A symbolic state and the operations of rules/domain.yaml acting on it (Sec. IX-C2).

A state is a frozenset of facts ``(predicate, arg, ...)``. An operation is
applied with bindings ``{parameter: name}`` (a list parameter binds a tuple of
names): ``check`` lists the preconditions that do not hold, ``apply`` removes
then adds its effects, ``find_bindings`` completes bindings from the state
(e.g. where a picked object rests). Pure functions: no rule names in here.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping

from lbw_engine.rules.domain import WILDCARD, Atom, OperationDomain

Fact = tuple[str, ...]
State = frozenset[Fact]
Bindings = Mapping[str, str | tuple[str, ...]]


def ground(atom: Atom, bindings: Bindings) -> list[Fact]:
    """The facts an atom stands for under ``bindings`` (one per list element)."""
    if atom.when is not None:
        size = len(_values(bindings, atom.when[1]))
        if (atom.when[0] == "single") != (size == 1):
            return []
    choices = [(WILDCARD,) if a == WILDCARD else _values(bindings, a) for a in atom.args]
    return [(atom.pred, *combo) for combo in itertools.product(*choices)]


def matches(pattern: Fact, fact: Fact) -> bool:
    """Does a fact match a pattern whose ``*`` arguments match anything?"""
    return len(pattern) == len(fact) and all(
        p in (WILDCARD, f) for p, f in zip(pattern, fact, strict=True))


def check(state: State, op: OperationDomain, bindings: Bindings,
          planner: bool = False) -> list[Fact]:
    """The preconditions of ``op`` that ``state`` lacks ([] when it may run).

    ``planner`` adds the preconditions only a planner must respect (domain.yaml
    ``planner-pre``).
    """
    atoms = (*op.pre, *op.planner_pre) if planner else op.pre
    return [f for atom in atoms for f in ground(atom, bindings) if f not in state]


def apply(state: State, op: OperationDomain, bindings: Bindings) -> State:
    """The state after ``op``: its removals (``*`` matches anything), then its additions."""
    gone = [p for atom in op.remove for p in ground(atom, bindings)]
    # Exact facts go by set difference; only patterns with `*` are matched one by one
    # (recognition repair runs whole sequences many times: docs/repair.md).
    loose = [p for p in gone if WILDCARD in p]
    kept = state.difference(gone)
    if loose:
        preds = {p[0] for p in loose}
        kept = {f for f in kept if f[0] not in preds or not any(matches(p, f) for p in loose)}
    return frozenset(kept | {f for atom in op.add for f in ground(atom, bindings)})


def find_bindings(state: State, op: OperationDomain, given: Bindings) -> dict:
    """``given`` extended from the state through the preconditions.

    Preconditions are matched in order; a list parameter binds every element
    that matches (the supports of an object resting on several), and an atom
    whose ``when`` does not fit what was found is skipped. Parameters no
    precondition names stay unbound; ``check`` the result before using it.
    """
    out = dict(given)
    for atom in op.pre:
        if all(a == WILDCARD or a[1:] in out for a in atom.args):
            continue
        found = _match(state, atom, out)
        if found is None:
            continue
        trial = {**out, **found}
        if atom.when is None or ground(atom, trial):
            out = trial
    return out


def _match(state: State, atom: Atom, bound: Bindings) -> dict | None:
    """Values for the atom's free parameters from the first matching facts."""
    known = [None if a == WILDCARD or a[1:] not in bound else _values(bound, a)
             for a in atom.args]
    hits = [f for f in sorted(state) if f[0] == atom.pred and len(f) == len(atom.args) + 1
            and all(k is None or v in k for k, v in zip(known, f[1:], strict=True))]
    if not hits:
        return None
    out: dict[str, list[str]] = {}
    first = hits[0]
    for i, arg in enumerate(atom.args):
        if arg == WILDCARD or known[i] is not None:
            continue
        out[arg[1:]] = [first[i + 1]]
    # Facts that agree with the first on all but one free argument add to a list
    # parameter there (one fact per support).
    for fact in hits[1:]:
        differ = [i for i, arg in enumerate(atom.args)
                  if arg != WILDCARD and known[i] is None and fact[i + 1] != first[i + 1]]
        if len(differ) == 1:
            name = atom.args[differ[0]][1:]
            if fact[differ[0] + 1] not in out[name]:
                out[name].append(fact[differ[0] + 1])
    return {k: v[0] if len(v) == 1 else tuple(sorted(v)) for k, v in out.items()}


def as_bindings(op: OperationDomain, values: Bindings) -> dict[str, str | tuple[str, ...]]:
    """Bindings with list parameters as tuples and single ones as names."""
    out: dict[str, str | tuple[str, ...]] = {}
    for name, value in values.items():
        if op.params[name].many:
            out[name] = (value,) if isinstance(value, str) else tuple(value)
        else:
            out[name] = value
    return out


def _values(bindings: Bindings, term: str) -> tuple[str, ...]:
    """The names a ``$param`` term is bound to (a list parameter binds several)."""
    value = bindings[term[1:]]
    return (value,) if isinstance(value, str) else tuple(value)


def run(state: State, steps: Iterable[tuple[OperationDomain, Bindings]],
        planner: bool = False) -> tuple[State, list[tuple[int, list[Fact]]]]:
    """Apply steps in order; also return (index, unmet preconditions) where a step could not run.

    A step whose preconditions do not hold is still applied, so one
    inconsistency does not hide the next (what recognition repair needs).
    """
    problems = []
    for index, (op, bindings) in enumerate(steps):
        unmet = check(state, op, bindings, planner)
        if unmet:
            problems.append((index, unmet))
        state = apply(state, op, bindings)
    return state, problems
