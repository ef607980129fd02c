"""A recognized action sequence run through rules/domain.yaml (Sec. IX-C2).

The paper proposes to check what was recognized against generic knowledge of
every operation: its preconditions and effects. Here each recognized operation
(actions.json: operation, base / target / special, the relations measured
before it) is bound to the parameters of its domain.yaml entry, and the
sequence is run on a symbolic state (lbw_engine.understand.domain). Every step
that cannot run as recognized is a ``Finding``: an unmet precondition, a
parameter nothing binds, or a name of the wrong type (an "object" that is the
table).

Binding a step, in order (no operation is named here: the rules say which slot
fills which parameter):

1. effects.yaml's ``bind`` and domain.yaml's ``bind``: a slot (base, target,
   special) or an environment node (the hand, the table);
2. a parameter of the hand's or the table's type (domain.yaml ``kinds``) is the
   hand or the table, when the sequence has exactly one;
3. a step that records a position (domain.yaml ``place:``) gets a place of its
   own, lying on the supports its support relation names (``site``) and owned
   by the object it puts there (``place-of``);
4. a place parameter no precondition names (where a carried object is taken)
   is the place of the next step that records one, when that step agrees with
   this one on every other parameter both have; else a place nothing lies on;
5. while running, the rest is found in the state (``find_bindings``: where a
   picked object rests).

The start: for each object, the relations of the first snapshot (an
operation's ``initial_state``) where it is the subject, taken no later than the
first operation that names it in a slot (nothing can have moved it before);
relations with a position get the object's starting place. domain.yaml's
``initial`` facts are added (docs/repair.md).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.names import HAND, TABLE
from lbw_engine.rules import SLOTS, RuleSet
from lbw_engine.rules.domain import FILE, Domain, OperationDomain
from lbw_engine.understand.domain import Fact, State, apply, check, find_bindings, ground

START = "start"  # the suffix of an object's place before the first operation
ENV_NODES = {"hand": HAND, "table": TABLE}  # effects.yaml bindings to environment nodes
Record = Mapping[str, Any]  # one operation of actions.json


@dataclass(frozen=True)
class Finding:
    """A step that cannot run as recognized."""

    index: int
    name: str  # the operation's name in actions.json (no02)
    operation: str
    problem: str  # what is wrong, in words

    def __str__(self) -> str:
        """``no02 (OPERATION): what is wrong`` (names are unique in a sequence)."""
        return f"{self.name} ({self.operation}): {self.problem}"


@dataclass(frozen=True)
class Start:
    """The symbolic world before the first operation."""

    rules: RuleSet
    types: dict[str, str]  # every name of the sequence -> its domain.yaml type
    facts: State

    @property
    def domain(self) -> Domain:
        """rules/domain.yaml."""
        return self.rules.domain

    def type_of(self, name: str) -> str:
        """A name's type; a name the sequence did not show is a movable object."""
        return self.types.get(name, self.domain.kinds["movable"])


@dataclass
class Bound:
    """One step's bindings before the run, and what could not be bound."""

    op: OperationDomain | None
    values: dict[str, Any] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    place: str | None = None  # the place this step records
    facts: frozenset[Fact] = frozenset()  # where that place lies and whose it is


@dataclass(frozen=True)
class Run:
    """The symbolic run of a sequence: its findings and each step's bindings."""

    findings: list[Finding]
    bindings: list[dict[str, Any]]

    @property
    def consistent(self) -> bool:
        """Every step ran as recognized."""
        return not self.findings


def relation_objects(rel: Sequence[Any]) -> tuple[str, ...]:
    """The object(s) of an actions.json relation ``[type, subject, object(s), {...}?]``."""
    return tuple(rel[2]) if isinstance(rel[2], list) else (rel[2],)


def start_state(ops: Sequence[Record], objects: Iterable[str], rules: RuleSet) -> Start:
    """The symbolic start of a recognized sequence (module docstring)."""
    domain = rules.domain
    agents, fixed = rules.analysis.agents, rules.analysis.fixed
    names = set(objects) | set(agents) | set(fixed)
    for op in ops:
        names |= {n for slot in SLOTS for n in op[slot]}
        for key in ("initial_state", "final_state"):
            names |= {n for r in op[key]["relations"] for n in (r[1], *relation_objects(r))}
    kind = {**{n: "agents" for n in agents}, **{n: "fixed" for n in fixed}}
    types = {n: domain.kinds[kind.get(n, "movable")] for n in sorted(names)}
    rels = [r for r in _first_seen(ops) if r[0] in domain.relations]
    support = {r[1]: relation_objects(r) for r in rels if r[0] in domain.support_relations}
    facts: set[Fact] = set()
    for r in rels:
        tail: tuple[str, ...] = ()
        if domain.placed(r[0]):
            owner = _owner(r, support, domain)
            if owner is None:
                continue  # a position of something whose support was not seen
            tail = (f"{owner}@{START}",)
        facts |= {(r[0], r[1], o, *tail) for o in relation_objects(r)}
    under = {o for objs in support.values() for o in objs}
    rows: dict[str, list[dict[str, str]]] = {
        "agent": [{"agent": a} for a in sorted(agents)],
        "free": [{"free": n} for n, t in types.items()
                 if t == domain.kinds["movable"] and n not in under],
    }
    for owner, objs in sorted(support.items()):
        facts |= place_facts(domain, f"{owner}@{START}", owner, objs)
    facts |= {f for each, atom in domain.initial for row in rows.get(each, ())
              for f in ground(atom, row)}
    return Start(rules, types, frozenset(facts))


def place_facts(domain: Domain, place: str, owner: str, supports: Iterable[str]) -> set[Fact]:
    """domain.yaml ``initial``'s site and owner facts of one place."""
    rows = {"site": [{"place": place, "support": s} for s in supports],
            "owner": [{"place": place, "owner": owner}]}
    return {f for each, atom in domain.initial for row in rows.get(each, ())
            for f in ground(atom, row)}


def _first_seen(ops: Sequence[Record]) -> list[Sequence[Any]]:
    """Each subject's relations in the first snapshot showing it, before anything moved it."""
    named: dict[str, int] = {}
    for i, op in enumerate(ops):
        for n in (n for slot in SLOTS for n in op[slot]):
            named.setdefault(n, i)
    out: list[Sequence[Any]] = []
    decided: set[str] = set()
    for i, op in enumerate(ops):
        shown: dict[str, list[Sequence[Any]]] = {}
        for rel in op["initial_state"]["relations"]:
            if rel[1] not in decided and i <= named.get(rel[1], len(ops)):
                shown.setdefault(rel[1], []).append(rel)
        decided |= set(shown)
        out += [r for rels in shown.values() for r in rels]
    return out


def _owner(rel: Sequence[Any], support: dict[str, tuple[str, ...]], domain: Domain) -> str | None:
    """Whose position a relation records: the object resting on all the others it names."""
    if rel[0] in domain.support_relations:
        return rel[1]
    terms = (rel[1], *relation_objects(rel))
    for n in terms:
        if n in support and {t for t in terms if t != n} <= set(support[n]):
            return n
    return None


def slot_values(source: Any, op: Record) -> tuple[str, ...] | None:
    """The names an effects.yaml / domain.yaml binding source gives (None: the state decides)."""
    if isinstance(source, dict):  # {nearest: SLOT, ...} or {found: ..., else: SLOT}
        source = source.get("nearest", source.get("else"))
    if source in SLOTS:
        return tuple(op[source])
    return (ENV_NODES[source],) if source in ENV_NODES else None


def binding_sources(rules: RuleSet, dom: OperationDomain) -> dict[str, Any]:
    """Parameter -> where its value comes from (effects.yaml's bind, then domain.yaml's)."""
    effects = rules.effects.get(dom.name)
    return {**(effects.bind if effects is not None else {}), **dom.bind}


class Binder:
    """Steps 1-3 of the module docstring, kept per operation record: a sequence that
    is run again with one operation changed binds only the changed one anew."""

    def __init__(self, start: Start) -> None:
        """Bind against ``start``."""
        self.start = start
        self._done: dict[int, tuple[Record, Bound]] = {}  # id(record) -> (record, bound)

    def static(self, op: Record) -> Bound:
        """The bindings of one operation record (its place named by a serial number)."""
        key = id(op)
        if key not in self._done:  # the record is kept, so its id is not reused
            self._done[key] = (op, bind_static(self.start, len(self._done), op))
        return self._done[key][1]


def bind_static(start: Start, serial: int, op: Record) -> Bound:
    """Steps 1-3 of the module docstring for one operation (``serial`` names its place)."""
    dom = start.domain.operations.get(op["operation"])
    if dom is None:
        return Bound(None, problems=[f"{op['operation']} has no entry in {FILE}"])
    bound = Bound(dom)
    for var, source in binding_sources(start.rules, dom).items():
        names, param = slot_values(source, op), dom.params.get(var)
        if param is None or not names:
            continue
        if param.many:
            bound.values[var] = names
        elif len(names) == 1:
            bound.values[var] = names[0]
        else:
            listed = ", ".join(names)
            bound.problems.append(f"${var} is one object, the slot names {listed}")
    unique = (start.domain.kinds["agents"], start.domain.kinds["fixed"])
    for p in dom.params.values():
        fits = [n for n, t in start.types.items() if t == p.type]
        if p.name not in bound.values and not p.many and p.type in unique and len(fits) == 1:
            bound.values[p.name] = fits[0]
    for var, value in bound.values.items():
        want = dom.params[var].type
        for n in (value,) if isinstance(value, str) else value:
            if not start.domain.is_a(start.type_of(n), want):
                bound.problems.append(f"${var} is {n}, a {start.type_of(n)}, not a {want}")
    _own_place(start, serial, bound)
    return bound


def _own_place(start: Start, serial: int, bound: Bound) -> None:
    """Step 3: the place a step that records a position puts its object at."""
    dom = bound.op
    if dom is None or dom.place is None:
        return
    var = dom.place[1:]
    trial = {**bound.values, var: var}
    try:
        placed = [f for a in dom.add if a.pred in start.domain.support_relations
                  and a.args[-1] == dom.place for f in ground(a, trial)]
    except KeyError:  # a parameter of the support relation is not bound
        return
    if placed:
        owner = placed[0][1]
        bound.place = f"{owner}@{serial}"
        bound.values[var] = bound.place
        bound.facts = frozenset(place_facts(start.domain, bound.place, owner,
                                            [f[2] for f in placed]))


def _announced(start: Start, bounds: list[Bound]) -> list[dict[str, str]]:
    """Step 4: a place no precondition names comes from the next step that records one."""
    out: list[dict[str, str]] = []
    for i, b in enumerate(bounds):
        found: dict[str, str] = {}
        out.append(found)
        if b.op is None:
            continue
        needed = {a[1:] for atom in b.op.pre for a in atom.args}
        for p in b.op.params.values():
            if p.name in b.values or p.many or p.name in needed \
                    or p.type != start.domain.place_type:
                continue
            nxt = next((c for c in bounds[i + 1:] if c.op is not None and c.op.place), None)
            if nxt is not None and nxt.place is not None and _agree(start, b, nxt):
                found[p.name] = nxt.place
            else:
                found[p.name] = f"{p.name}@{i}"  # a place nothing lies on
    return out


def _agree(start: Start, a: Bound, b: Bound) -> bool:
    """Both steps bind every parameter they share (places aside) to the same names."""
    assert a.op is not None and b.op is not None
    shared = [q for q, p in a.op.params.items()
              if q in b.op.params and p.type != start.domain.place_type]
    return all(a.values.get(q) is not None and a.values.get(q) == b.values.get(q)
               for q in shared)


def run_sequence(start: Start, ops: Sequence[Record], binder: Binder | None = None,
                 stop: Callable[[Finding], bool] | None = None) -> Run:
    """Bind every step, then run them in order.

    A step that cannot run is still applied when it is bound, so one
    inconsistency does not hide the next. Where ``stop(finding)`` holds the run
    ends (a repair candidate already known to be of no use).
    """
    binder = binder or Binder(start)
    bounds = [binder.static(op) for op in ops]
    announced = _announced(start, bounds)
    state = start.facts.union(*(b.facts for b in bounds))
    findings: list[Finding] = []
    bindings: list[dict[str, Any]] = []
    for i, (op, b) in enumerate(zip(ops, bounds, strict=True)):
        problems, values = list(b.problems), {**b.values, **announced[i]}
        if b.op is not None:
            values = find_bindings(state, b.op, values)
            missing = [f"${p}" for p in b.op.params if p not in values]
            if missing:
                problems.append("nothing to bind " + ", ".join(missing) + " to")
            else:
                unmet = check(state, b.op, values)
                if unmet:
                    problems.append("needs " + ", ".join(" ".join(f) for f in unmet))
                state = apply(state, b.op, values)
        bindings.append(values)
        if problems:
            name = op.get("name") or f"#{i}"
            findings.append(Finding(i, name, op["operation"], "; ".join(problems)))
            if stop is not None and stop(findings[-1]):
                break
    return Run(findings, bindings)
