"""rules/effects.yaml: what each operation changes in the environment model (Sec. V-B4).

The relations, the roles the interpreter needs by name (hold, single and
multiple support) and one effect rule per operation: bindings, relation
templates to remove and to add, and how the object moves.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lbw_engine.rules import records as R
from lbw_engine.rules.reader import Reader
from lbw_engine.yamlio import line_of


def _template(reader: Reader, item: Any, container: Any, index: int, relations) -> R.Template:
    """One relation template of effects.yaml."""
    when = None
    if isinstance(item, dict):
        reader.keys(item, "a relation rule", ("relation",), ("when",))
        cond = reader.mapping(item.get("when", {}), "when", item, "when")
        reader.keys(cond, "when", (), ("single", "multiple"))
        if len(cond) != 1:
            reader.fail("when needs exactly one of single / multiple", item, "when")
        ((kind, var),) = cond.items()
        when = (kind, str(var))
        item = item["relation"]
    item = reader.sequence(item, "a relation template", container, index)
    if len(item) not in (3, 4):
        reader.fail(
            "a relation template is [type, subject, object] or with {wrt: ...}", container, index
        )
    rtype = reader.one_of(item[0], relations, "relation", container, index)
    wrt = None
    if len(item) == 4:
        extra = reader.mapping(item[3], "the :at part", container, index)
        reader.keys(extra, "the :at part", ("wrt",))
        wrt = str(extra["wrt"])
    at = R.Where(reader.file, line_of(container, index))
    return R.Template(rtype, str(item[1]), str(item[2]), wrt, when, at)


def _roles(reader: Reader, data: dict, relations: tuple[str, ...]) -> R.Roles:
    """The relations named by role: hold, and support single / multiple."""
    roles = reader.mapping(data["roles"], "roles", data, "roles")
    reader.keys(roles, "roles", ("hold", "support"))
    support = reader.mapping(roles["support"], "roles.support", roles, "support")
    reader.keys(support, "roles.support", ("single", "multiple"))
    hold = reader.one_of(roles["hold"], relations, "relation", roles, "hold")
    single = reader.one_of(support["single"], relations, "relation", support, "single")
    multiple = reader.one_of(support["multiple"], relations, "relation", support, "multiple")
    if len({hold, single, multiple}) < 3:
        reader.fail("the hold, single and multiple roles need three different relations",
                    data, "roles")
    return R.Roles(hold, single, multiple)


def read_effects(directory: Path) -> tuple[tuple[str, ...], R.Roles, dict[str, R.EffectRule]]:
    """Parse rules/effects.yaml: the relations, their roles and each operation's effect."""
    reader, data = Reader.load(directory / "effects.yaml", ("relations", "roles", "operations"))
    relations = reader.names(data, "relations", "relations")
    if len(set(relations)) != len(relations):
        reader.fail("a relation is listed twice", data, "relations")
    roles = _roles(reader, data, relations)
    effects: dict[str, R.EffectRule] = {}
    table = reader.mapping(data["operations"], "operations", data, "operations")
    for op, spec in table.items():
        spec = reader.mapping(spec, f"effects of {op!r}", table, op)
        reader.keys(spec, f"effects of {op!r}", ("bind",), ("remove", "add", "move"))
        bind = reader.mapping(spec["bind"], "bind", spec, "bind")
        for var, value in bind.items():
            if isinstance(value, dict) and "found" in value:
                reader.keys(value, f"binding of {var!r}", ("found", "else"))
                if not isinstance(value["found"], str):
                    reader.fail(f"binding of {var!r}: found must name a feature", value, "found")
                reader.one_of(value["else"], R.BINDINGS, "binding", value, "else")
            elif isinstance(value, dict):
                reader.keys(value, f"binding of {var!r}", ("nearest", "to"))
                reader.one_of(value["nearest"], R.BINDINGS, "binding", value, "nearest")
            else:
                reader.one_of(value, R.BINDINGS, "binding", bind, var)
        groups = {}
        for key in ("remove", "add"):
            items = reader.sequence(spec.get(key, []), key, spec, key)
            groups[key] = tuple(
                _template(reader, it, items, i, relations) for i, it in enumerate(items)
            )
        move = reader.mapping(spec.get("move", {}), "move", spec, "move")
        if move:
            shapes = (("follow", "object"), ("place", "on", "measured"))
            if tuple(move) not in shapes:
                reader.fail(
                    "move is {follow: $h, object: $o} or {place: $o, on: $s, measured: FEATURE}",
                    spec,
                    "move",
                )
        at = R.Where(reader.file, line_of(table, op))
        effects[op] = R.EffectRule(op, dict(bind), groups["remove"], groups["add"], dict(move), at)
    return relations, roles, effects
