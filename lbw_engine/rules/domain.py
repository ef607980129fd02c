"""rules/domain.yaml: each operation's parameters, preconditions and effects (Sec. IX-C2).

The symbolic domain is checked at load time against the other rule files: its
operations are operations of operations.yaml (one it leaves out is unknown to
the symbolic checks and the export, which say so when they meet it), its
relations are exactly effects.yaml's, and an operation's effects on those relations are taken from
effects.yaml (compiled here into the same atom form as the preconditions), so
no fact is written twice. Errors name domain.yaml (or effects.yaml) and the line.

Atoms are ``(predicate, args, when)``: an argument is ``$name`` (a parameter;
a list parameter stands for one fact per element) or ``*`` (matches anything;
removals only); ``when`` is ``("single" | "multiple", "$list")`` or None.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from lbw_engine import rules as R
from lbw_engine.rules.reader import Reader
from lbw_engine.yamlio import line_of, load_file

FILE = "domain.yaml"
WILDCARD = "*"
WHEN_KINDS = ("single", "multiple")
ATOM_LISTS = ("pre", "planner-pre", "add", "remove")
KINDS = ("agents", "fixed", "movable")  # analysis.yaml's object roles, and the rest
# `initial` generators: what each ranges over -> the variables it binds.
EACH = {"agent": ("agent",), "free": ("free",), "site": ("place", "support"),
        "owner": ("place", "owner")}


@dataclass(frozen=True)
class Atom:
    """A predicate over terms; ``when`` restricts it to lists of one or several."""

    pred: str
    args: tuple[str, ...]
    when: tuple[str, str] | None = None

    def variables(self) -> set[str]:
        """The parameter names this atom uses (without ``$``)."""
        names = {a[1:] for a in self.args if a != WILDCARD}
        return names | ({self.when[1][1:]} if self.when else set())


@dataclass(frozen=True)
class Param:
    """An operation parameter: its type, and whether it is a list (of supports)."""

    name: str
    type: str
    many: bool = False


@dataclass(frozen=True)
class OperationDomain:
    """One operation: parameters, preconditions and effects (own and effects.yaml's)."""

    name: str
    params: dict[str, Param]
    bind: dict[str, str]  # parameter -> ACT-node slot, where effects.yaml does not bind it
    pre: tuple[Atom, ...]
    planner_pre: tuple[Atom, ...]  # only a planner must respect these (domain.yaml)
    add: tuple[Atom, ...]
    remove: tuple[Atom, ...]
    place: str | None  # the parameter naming the position this operation records
    line: int | None = None


@dataclass(frozen=True)
class Domain:
    """The loaded symbolic domain."""

    file: str
    types: dict[str, str | None]  # type -> parent type
    predicates: dict[str, tuple[str, ...]]  # every predicate (own and relations): arg types
    relations: tuple[str, ...]  # effects.yaml's relations, in its order
    support_relations: tuple[str, ...]  # effects.yaml's support-relations
    place_type: str | None = None  # the type of the operations' `place` parameters
    kinds: dict[str, str] = field(default_factory=dict)  # object kind -> type
    initial: tuple[tuple[str, Atom], ...] = ()  # (each, atom): what holds at the start
    operations: dict[str, OperationDomain] = field(default_factory=dict)

    def is_a(self, kind: str, ancestor: str) -> bool:
        """``kind`` is ``ancestor`` or one of its subtypes."""
        seen: str | None = kind
        while seen is not None:
            if seen == ancestor:
                return True
            seen = self.types[seen]
        return False

    def placed(self, pred: str) -> bool:
        """Does this predicate carry a place as its last argument?"""
        types = self.predicates[pred]
        return bool(types) and self.place_type is not None and types[-1] == self.place_type


def load_domain(rules_dir: str | Path | None = None) -> Domain:
    """The symbolic domain of a rules folder (read, with every other file, by load_rules)."""
    return R.load_rules(rules_dir).domain


def parse(rules: R.RuleSet) -> Domain:
    """Read rules/domain.yaml and check it against the other rule files."""
    path = rules.directory / FILE
    reader = Reader(path)
    data = reader.mapping(load_file(path), "the file")
    reader.keys(data, "the file",
                ("types", "predicates", "kinds", "initial", "relations", "operations"))
    types = _types(reader, data)
    predicates = _predicates(reader, data, "predicates", types)
    for name in predicates:
        if name in rules.relations:
            reader.fail(f"predicate {name!r} is a relation of effects.yaml; declare its "
                        "argument types under 'relations'", data["predicates"], name)
    relations = _predicates(reader, data, "relations", types)
    for name in relations:
        reader.one_of(name, rules.relations, "relation (of effects.yaml)", data["relations"], name)
    for name in rules.relations:
        if name not in relations:
            reader.fail(f"relation {name!r} of effects.yaml has no argument types here",
                        data, "relations")
    table = reader.mapping(data["operations"], "operations", data, "operations")
    domain = Domain(str(path), types, {**predicates, **relations}, tuple(rules.relations),
                    tuple(rules.support_relations), _place_type(reader, table),
                    _kinds(reader, data, types))
    domain = replace(domain, initial=_initial(reader, data, domain))
    for name, spec in table.items():
        reader.one_of(name, rules.operations, "operation (of operations.yaml)", table, name)
        domain.operations[name] = _operation(reader, domain, name, spec, table, rules)
    return domain


def _kinds(reader: Reader, data: dict, types: dict) -> dict[str, str]:
    """``kinds``: the type of the agents, the fixed objects and the movable ones."""
    table = reader.mapping(data["kinds"], "kinds", data, "kinds")
    reader.keys(table, "kinds", KINDS)
    for kind, name in table.items():
        reader.one_of(name, types, f"kinds {kind}: type", table, kind)
    return dict(table)


def _initial(reader: Reader, data: dict, domain: Domain) -> tuple[tuple[str, Atom], ...]:
    """``initial``: ``{each: agent|free|site, atom: [...]}`` rows."""
    rows = reader.sequence(data["initial"], "initial", data, "initial")
    out = []
    for i, row in enumerate(rows):
        row = reader.mapping(row, f"initial[{i}]", rows, i)
        reader.keys(row, f"initial[{i}]", ("each", "atom"))
        each = reader.one_of(row["each"], EACH, "initial: each", row, "each")
        kinds = {"agent": domain.kinds["agents"], "free": domain.kinds["movable"],
                 "place": domain.place_type or "", "support": domain.kinds["movable"],
                 "owner": domain.kinds["movable"]}
        params = {v: Param(v, kinds[v]) for v in EACH[each] if kinds[v] in domain.types}
        out.append((each, _atom(reader, domain, params, "initial", row["atom"], row, "atom",
                                f"initial[{i}]")))
    return tuple(out)


def _place_type(reader: Reader, table: dict) -> str | None:
    """The type of every operation's ``place`` parameter (one type for all)."""
    found = None
    for name, spec in table.items():
        if not isinstance(spec, dict) or not isinstance(spec.get("place"), str):
            continue
        params = spec.get("params") if isinstance(spec.get("params"), dict) else {}
        kind = params.get(spec["place"][1:])
        if isinstance(kind, str) and found not in (None, kind):
            reader.fail(f"operation {name}: places are of type {found!r}, not {kind!r}",
                        spec, "place")
        found = kind if isinstance(kind, str) else found
    return found


def _types(reader: Reader, data: dict) -> dict[str, str | None]:
    """``types``: name -> parent or null; parents declared, no cycles."""
    table = reader.mapping(data["types"], "types", data, "types")
    for name, parent in table.items():
        if parent is not None:
            reader.one_of(parent, table, "parent type", table, name)
        seen, at = {name}, parent
        while at is not None:
            if at in seen:
                reader.fail(f"type {name!r} is its own ancestor", table, name)
            seen.add(at)
            at = table[at]
    return dict(table)


def _predicates(reader: Reader, data: dict, key: str, types: dict) -> dict[str, tuple[str, ...]]:
    """A mapping of predicate -> list of argument types."""
    table = reader.mapping(data[key], key, data, key)
    out = {}
    for name, args in table.items():
        args = reader.sequence(args, f"the argument types of {name!r}", table, name)
        for arg in args:
            reader.one_of(arg, types, f"argument type of {name!r}:", table, name)
        out[name] = tuple(args)
    return out


def _operation(reader: Reader, domain: Domain, name: str, spec: Any, table: dict,
               rules: R.RuleSet) -> OperationDomain:
    """One entry of ``operations``."""
    what = f"operation {name}"
    spec = reader.mapping(spec, what, table, name)
    reader.keys(spec, what, ("params",), ("bind", "place", *ATOM_LISTS))
    params = _params(reader, domain, spec, what)
    effects = rules.effects.get(name)
    bind = reader.mapping(spec.get("bind", {}), f"{what} bind", spec, "bind")
    for var, slot in bind.items():
        reader.one_of(var, params, f"{what} bind: parameter", bind, var)
        reader.one_of(slot, R.SLOTS, f"{what} bind: slot", bind, var)
        if effects is not None and var in effects.bind:
            reader.fail(f"{what} bind: effects.yaml already binds ${var}", bind, var)
    place = spec.get("place")
    if place is not None:
        _term(reader, params, place, spec, "place", what)
        if params[place[1:]].many:
            reader.fail(f"{what}: the place parameter cannot be a list", spec, "place")
    lists = {key: tuple(_atom(reader, domain, params, key, item, spec[key], i, what)
                        for i, item in enumerate(reader.sequence(spec[key], f"{what} {key}",
                                                                 spec, key)))
             for key in ATOM_LISTS if key in spec}
    add, remove = lists.get("add", ()), lists.get("remove", ())
    if effects is not None:
        add += tuple(_from_effects(t, domain, params, place, effects, removal=False)
                     for t in effects.add)
        remove += tuple(_from_effects(t, domain, params, place, effects, removal=True)
                        for t in effects.remove)
    return OperationDomain(name, params, dict(bind), lists.get("pre", ()),
                           lists.get("planner-pre", ()), add, remove, place,
                           line_of(table, name))


def _params(reader: Reader, domain: Domain, spec: dict, what: str) -> dict[str, Param]:
    """``params``: name -> type, or [type] for a list."""
    table = reader.mapping(spec["params"], f"{what} params", spec, "params")
    out = {}
    for var, kind in table.items():
        many = isinstance(kind, list)
        if many and len(kind) != 1:
            reader.fail(f"{what}: a list parameter is written [type]", table, var)
        kind = kind[0] if many else kind
        reader.one_of(kind, domain.types, f"{what}: type of ${var}", table, var)
        out[var] = Param(var, kind, many)
    return out


def _term(reader: Reader, params: dict[str, Param], term: Any, container: Any, key: Any,
          what: str, wildcard: bool = False) -> str:
    """A term: ``$param`` (``$param*`` means the same), or ``*`` where allowed."""
    if wildcard and term == WILDCARD:
        return term
    if not isinstance(term, str) or not term.startswith("$"):
        reader.fail(f"{what}: {term!r} is not a parameter ($name)"
                    + (" or '*'" if wildcard else ""), container, key)
    var = term[1:].removesuffix("*")
    reader.one_of(var, params, f"{what}: parameter", container, key)
    return "$" + var


def _atom(reader: Reader, domain: Domain, params: dict[str, Param], key: str, item: Any,
          container: Any, index: int, what: str) -> Atom:
    """``[pred, term...]`` or ``{atom: [...], when: {single|multiple: $list}}``."""
    when = None
    if isinstance(item, dict):
        reader.keys(item, f"{what} {key}[{index}]", ("atom", "when"))
        cond = reader.mapping(item["when"], "when", item, "when")
        if len(cond) != 1:
            reader.fail(f"{what}: 'when' has one key: single or multiple", item, "when")
        (kind, var), = cond.items()
        reader.one_of(kind, WHEN_KINDS, f"{what}: when", item, "when")
        var = _term(reader, params, var, item, "when", what)
        if not params[var[1:]].many:
            reader.fail(f"{what}: 'when' needs a list parameter, ${var[1:]} is not", item, "when")
        when, item = (kind, var), item["atom"]
    item = reader.sequence(item, f"{what} {key}[{index}]", container, index)
    if not item:
        reader.fail(f"{what}: an atom is [predicate, term...]", container, index)
    pred = reader.one_of(item[0], domain.predicates, "predicate", container, index)
    types = domain.predicates[pred]
    if len(item) - 1 != len(types):
        reader.fail(f"{what}: {pred} takes {len(types)} arguments, got {len(item) - 1}",
                    container, index)
    args = tuple(_term(reader, params, t, container, index, what, wildcard=key == "remove")
                 for t in item[1:])
    for arg, kind in zip(args, types, strict=True):
        if arg != WILDCARD and not _related(domain, params[arg[1:]].type, kind):
            reader.fail(f"{what}: {arg} is a {params[arg[1:]].type}, but {pred} wants a "
                        f"{kind} there", container, index)
    return Atom(pred, args, when)


def _related(domain: Domain, a: str, b: str) -> bool:
    """A parameter fits an argument when one type is the other or a subtype of it."""
    return domain.is_a(a, b) or domain.is_a(b, a)


def _from_effects(t: R.Template, domain: Domain, params: dict[str, Param], place: str | None,
                  effects: R.EffectRule, removal: bool) -> Atom:
    """An effects.yaml template as an atom of this domain (Sec. V-B4 -> symbolic).

    A template that records a position (``{wrt: ...}``) gets the operation's place
    as last argument; a removal without one matches the relation at any place.
    """
    def term(text: str) -> str:
        if text == WILDCARD:
            return text
        var = text[1:].removesuffix("*")
        if var not in params:
            raise t.at.error(f"variable ${var} of {effects.operation} is not a parameter of "
                             f"{effects.operation} in {FILE}")
        return "$" + var

    args = [term(t.subject), term(t.object)]
    if domain.placed(t.type):
        if t.wrt is not None:
            if place is None:
                raise t.at.error(f"{effects.operation} records a position, but {FILE} names no "
                                 "'place' parameter for it")
            args.append(place)
        elif removal:
            args.append(WILDCARD)
        else:
            raise t.at.error(f"relation {t.type} carries a place in {FILE}, but this template "
                             "records no position ({wrt: ...})")
    when = (t.when[0], term(t.when[1])) if t.when else None
    return Atom(t.type, tuple(args), when)

