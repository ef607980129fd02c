"""A learned plan as a symbolic planning problem over rules/domain.yaml.

The initial state is the root operator's SC⁻ (the relations the task changes,
as measured while watching) and the goal its SC⁺ (design.md "Plan"). A
relation that records a position (``:at ... :wrt``) gets a *place*: one per
object for where it rests at the start, one per object for where the task puts
it; each place lies on the supports of its relation (``site``). Relations on
several supports become one fact per support. The facts of domain.yaml's
``initial`` are added (the hand empty, nothing on the free objects, the sites).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from lbw_engine.do.plan import Plan, Relation
from lbw_engine.errors import InputError
from lbw_engine.rules.domain import Domain
from lbw_engine.understand.domain import Fact, State, ground

START, GOAL = "now", "goal"  # the two place families: where an object starts, where it goes


@dataclass
class Place:
    """A symbolic position: the relation that taught it, and its supports."""

    name: str
    owner: str  # the object the relation places
    supports: tuple[str, ...]
    relations: list[Relation] = field(default_factory=list)  # taught relations at this place


@dataclass
class SymbolicProblem:
    """Objects with their types, initial and goal facts, and the places."""

    domain: Domain
    objects: dict[str, str]  # name -> type
    init: State
    goal: State
    places: dict[str, Place]
    taught: dict[Fact, Relation]  # a fact of the goal -> the plan relation it came from

    def of_type(self, kind: str) -> list[str]:
        """Objects of ``kind`` or a subtype, by name."""
        return sorted(n for n, t in self.objects.items() if self.domain.is_a(t, kind))


def build(plan: Plan, domain: Domain, agents: frozenset[str],
          fixed: frozenset[str]) -> SymbolicProblem:
    """The symbolic problem of ``plan``: root SC⁻ to root SC⁺."""
    root = plan.operators[plan.root]
    objects = _objects(plan, domain, agents, fixed)
    names = set(objects)
    places: dict[str, Place] = {}
    init = _facts(root.sc_minus, START, domain, places, names, plan, "sc_minus")
    taught: dict[Fact, Relation] = {}
    goal = _facts(root.sc_plus, GOAL, domain, places, names, plan, "sc_plus", taught)
    problem = SymbolicProblem(domain, objects, frozenset(), frozenset(goal), places, taught)
    problem.init = frozenset(init) | _initial(problem, init)
    return problem


def _objects(plan: Plan, domain: Domain, agents: frozenset[str],
             fixed: frozenset[str]) -> dict[str, str]:
    """Every object the plan names, typed by its kind (domain.yaml ``kinds``)."""
    out: dict[str, str] = {}
    for op in plan.operators.values():
        named = [n for slot in op.slots.values() for n in slot]
        for r in (*op.sc_plus, *op.sc_minus):
            named += [r.subject, *r.objects]
        for n in named:
            kind = "agents" if n in agents else "fixed" if n in fixed else "movable"
            out[n] = domain.kinds[kind]
    return dict(sorted(out.items()))


def _facts(relations: tuple[Relation, ...], family: str, domain: Domain,
           places: dict[str, Place], names: set[str], plan: Plan, slot: str,
           taught: dict[Fact, Relation] | None = None) -> set[Fact]:
    """The facts of a set of relations (the root's SC⁻ or SC⁺)."""
    where = f"operators.{plan.root}.{slot}"
    placed = {r.subject: r for r in relations if r.type in domain.support_relations}
    out: set[Fact] = set()
    for r in relations:
        if r.type not in domain.relations:
            raise InputError(f"relation '{r.type}' is not a relation of effects.yaml "
                             f"({', '.join(domain.relations)})", file=plan.file, where=where)
        tail: tuple[str, ...] = ()
        if domain.placed(r.type):
            owner = _owner(r, placed)
            if owner is None:
                raise InputError(f"relation {r.type} {r.subject} records a position, but "
                                 f"no {'/'.join(domain.support_relations)} relation here "
                                 "places its objects", file=plan.file, where=where)
            place = _place(places, owner, family, placed[owner], names)
            place.relations.append(r)
            tail = (place.name,)
        for obj in r.objects:
            fact = (r.type, r.subject, obj, *tail)
            out.add(fact)
            if taught is not None:
                taught[fact] = r
    return out


def _owner(r: Relation, placed: dict[str, Relation]) -> str | None:
    """The object a relation's position belongs to: the one resting on the others.

    For a support relation that is its subject; for one between a placed object
    and one of its supports (co-support) it is the placed object.
    """
    terms = (r.subject, *r.objects)
    for n in terms:
        others = {t for t in terms if t != n}
        if n in placed and others <= set(placed[n].objects):
            return n
    return None


def _place(places: dict[str, Place], owner: str, family: str, support: Relation,
           names: set[str]) -> Place:
    """The place of ``owner`` in a family, made on first use; never an object's name."""
    for p in places.values():
        if p.owner == owner and p.name.startswith(f"{owner}-{family}"):
            return p
    name = f"{owner}-{family}"
    while name in names or name in places:
        name += "-"
    places[name] = Place(name, owner, support.objects)
    return places[name]


def _initial(problem: SymbolicProblem, facts: set[Fact]) -> frozenset[Fact]:
    """domain.yaml ``initial``: facts for each agent, free object and site."""
    domain = problem.domain
    under = {f[2] for f in facts if f[0] in domain.support_relations}
    rows: dict[str, list[dict[str, str]]] = {
        "agent": [{"agent": a} for a in problem.of_type(domain.kinds["agents"])],
        "free": [{"free": b} for b in problem.of_type(domain.kinds["movable"])
                 if b not in under],
        "site": [{"place": p.name, "support": s} for p in problem.places.values()
                 for s in p.supports],
        "owner": [{"place": p.name, "owner": p.owner} for p in problem.places.values()],
    }
    return frozenset(f for each, atom in domain.initial for b in rows[each]
                     for f in ground(atom, b))

