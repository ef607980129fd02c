"""A planner's plan over the exported domain, back as an executable plan.json document.

The planner's actions are replayed through the symbolic domain; every run of
actions that ends with a placement (an action adding a support relation)
becomes an ACHIEVE (Sec. VI-C1), whose SC⁺ / SC⁻ are the relations the run
added / removed. A relation at a place gets the taught ``:at ... :wrt`` of
that place (the learned plan's SC⁺ relation), so the tracer puts the object
where the demonstration did (Sec. VII-A). Actions after the last placement
join the last ACHIEVE. The root is a BUILD of the ACHIEVEs in planner order.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.do.plan import SLOTS, Relation
from lbw_engine.export.problem import SymbolicProblem
from lbw_engine.understand.domain import Fact, State, apply, check

Action = tuple[str, dict]  # (operation, domain bindings)


def executable_plan(sp: SymbolicProblem, actions: list[Action], root_class: str,
                    step_class: str) -> dict[str, Any]:
    """A plan.json document that runs ``actions`` (checked step by step)."""
    domain = sp.domain
    state: State = sp.init
    runs: list[list[tuple[Action, State, State]]] = [[]]
    for i, (operation, bindings) in enumerate(actions):
        op = domain.operations[operation]
        unmet = check(state, op, bindings, planner=True)
        if unmet:
            raise ValueError(f"step {i + 1} ({operation}) lacks {unmet}")
        after = apply(state, op, bindings)
        runs[-1].append(((operation, bindings), state, after))
        placed = any(f[0] in domain.support_relations for f in after - state)
        state = after
        if placed:
            runs.append([])
    if not runs[-1]:
        runs.pop()
    elif len(runs) > 1:
        runs[-2].extend(runs.pop())
    operators: dict[str, Any] = {}
    counter = [0]
    names = [_achieve(sp, run, f"{step_class.lower()}{k:02d}", step_class, operators, counter)
             for k, run in enumerate(runs, 1)]
    root = f"{root_class.lower()}01"
    learned_plus = [_json(r) for r in sp.taught.values()]
    operators = {root: {"class": root_class, **_slots(operators, names),
                        "sc_plus": _unique(learned_plus), "sc_minus": [], "si": [], "sp": [],
                        "plot": ["$sequence", *(["$action", n] for n in names)], "next": []},
                 **operators}
    return {"root": root, "operators": operators}


def _achieve(sp: SymbolicProblem, run: list, name: str, cls: str, operators: dict,
             counter: list[int]) -> str:
    """One ACHIEVE operator: the run's actions as leaves, its state change as SC⁺ / SC⁻."""
    start, end = run[0][1], run[-1][2]
    leaves = []
    for (operation, _), _, _ in run:
        counter[0] += 1
        leaves.append(f"{operation.lower()}{counter[0]:02d}")
    plus = _relations(sp, end - start)
    minus = _relations(sp, start - end)
    supports = [r for r in plus if r[0] in sp.domain.support_relations]
    base = sorted({r[1] for r in supports})
    target = sorted({o for r in supports for o in (r[2] if isinstance(r[2], list) else [r[2]])})
    operators[name] = {"class": cls, "base": base, "target": target, "special": [],
                       "sc_plus": plus, "sc_minus": minus, "si": [], "sp": [],
                       "plot": ["$sequence", *(["$action", leaf] for leaf in leaves)],
                       "next": []}
    return name


def _relations(sp: SymbolicProblem, facts: set[Fact]) -> list[list]:
    """Facts of the relations (not the domain's own predicates) as plan.json relations.

    Facts that differ only in one object (one per support) make one relation
    with a list of objects; a fact at a place gets that place's taught frame.
    """
    groups: dict[tuple, list[str]] = {}
    for f in sorted(facts):
        if f[0] not in sp.domain.relations:
            continue
        placed = sp.domain.placed(f[0])
        key = (f[0], f[1], f[3] if placed else None)
        groups.setdefault(key, []).append(f[2])
    out = []
    for (pred, subject, place), objs in groups.items():
        rel: list = [pred, subject, objs[0] if len(objs) == 1 else objs]
        taught = _taught(sp, pred, subject, place)
        if taught is not None and taught.at is not None:
            rel.append({"at": list(taught.at), "wrt": taught.wrt})
        out.append(rel)
    return out


def _taught(sp: SymbolicProblem, pred: str, subject: str, place: str | None) -> Relation | None:
    """The learned relation behind a fact: same predicate at the same place, same subject first."""
    if place is None or place not in sp.places:
        return None
    rels = [r for r in sp.places[place].relations if r.type == pred]
    return next((r for r in rels if r.subject == subject), rels[0] if rels else None)


def _json(r: Relation) -> list:
    """A plan relation in plan.json form."""
    out: list = [r.type, r.subject, list(r.objects) if r.multiple else r.objects[0]]
    if r.at is not None:
        out.append({"at": list(r.at), "wrt": r.wrt})
    return out


def _unique(rels: list[list]) -> list[list]:
    """Relations without repeats, in first-seen order."""
    seen, out = set(), []
    for r in rels:
        key = repr(r)
        if key not in seen:
            seen.add(key)
            out.append(r)
    return out


def _slots(operators: dict, names: list[str]) -> dict[str, list[str]]:
    """base / target / special of the root: those of its ACHIEVEs."""
    return {slot: sorted({n for name in names for n in operators[name][slot]}) for slot in SLOTS}
