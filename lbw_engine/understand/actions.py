"""Reading actions.json (design.md "Recognized actions") for plan analysis.

Only what analysis needs is required, so hand-written files work: per operation
``operation``, ``base``, ``target``, ``special``, ``initial_state.relations``
and ``final_state.relations``. ``name`` is optional; a missing one becomes the
operation in lower case plus a per-operation counter (``reach01``), the form of
Fig. 12. Every problem is an InputError naming the file and the key path.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError, read_input
from lbw_engine.understand.gcpause import without_gc
from lbw_engine.understand.relations import Rel, RelationTable

# Names must be writable in the plot notation of plan.txt (rules/plot.lark NAME).
SYMBOL = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+\-]*\Z")
STATE_KEYS = ("initial_state", "final_state")
SLOT_KEYS = ("base", "target", "special")


@dataclass(frozen=True)
class Operation:
    """One recognized operation: a leaf of the plan (Fig. 12)."""

    index: int
    name: str
    operation: str
    base: tuple[str, ...]
    target: tuple[str, ...]
    special: tuple[str, ...]
    initial: frozenset[Rel]  # IS
    final: frozenset[Rel]  # FS


@dataclass(frozen=True)
class ActionSequence:
    """The operations of one actions.json, in order, and its measured objects."""

    file: str
    operations: tuple[Operation, ...]
    objects: dict[str, Any] | None


def load_actions(path: str | Path, table: RelationTable) -> ActionSequence:
    """Read and check an actions.json file; relations are interned into ``table``."""
    return parse_actions(read_actions(path), table, str(path))


def read_actions(path: str | Path) -> Any:
    """The JSON document of an actions.json file (not yet checked: ``parse_actions``)."""
    path = Path(path)
    text = read_input(path, expected="an actions.json file")
    try:
        return json.loads(text, parse_constant=_reject_constant)
    except json.JSONDecodeError as exc:
        raise InputError(f"invalid JSON: {exc.msg}", file=path, line=exc.lineno) from None
    except ValueError as exc:
        raise InputError(str(exc), file=path) from None


def _reject_constant(name: str) -> Any:
    """JSON's NaN/Infinity extensions are not positions."""
    raise ValueError(f"invalid JSON: {name} is not a number allowed in actions.json")


@without_gc
def parse_actions(doc: Any, table: RelationTable, file: str = "<actions>") -> ActionSequence:
    """Check an actions.json document and build the ActionSequence."""

    def fail(message: str, where: str | None = None) -> InputError:
        return InputError(message, file=file, where=where)

    if not isinstance(doc, dict) or "operations" not in doc:
        raise fail("an actions file must be a JSON object with an 'operations' list")
    raw_ops = doc["operations"]
    if not isinstance(raw_ops, list):
        raise fail("must be a list of operations", "operations")
    if not raw_ops:
        raise fail("the action sequence is empty: there is nothing to analyze", "operations")
    objects = doc.get("objects")
    if objects is not None and not isinstance(objects, dict):
        raise fail("must be an object of name -> {shape, position}", "objects")
    counters: dict[str, int] = {}
    seen: dict[str, str] = {}
    ops = []
    for i, raw in enumerate(raw_ops):
        op = _operation(i, raw, table, counters, fail)
        if op.name in seen:
            raise fail(f"duplicate operation name {op.name!r} (also {seen[op.name]})",
                       f"operations[{i}].name")
        seen[op.name] = f"operations[{i}]"
        ops.append(op)
    return ActionSequence(file, tuple(ops), dict(objects) if objects is not None else None)


def _operation(i: int, raw: Any, table: RelationTable, counters: dict[str, int], fail) -> Operation:
    """One entry of ``operations``."""
    w = f"operations[{i}]"
    if not isinstance(raw, dict):
        raise fail("must be an object", w)
    for key in ("operation", *SLOT_KEYS, *STATE_KEYS):
        if key not in raw:
            raise fail(f"missing the required key {key!r}", w)
    operation = raw["operation"]
    if not isinstance(operation, str) or not SYMBOL.match(operation):
        raise fail(f"must be an operation name, got {operation!r}", f"{w}.operation")
    counters[operation] = counters.get(operation, 0) + 1
    name = raw.get("name", f"{operation.lower()}{counters[operation]:02d}")
    if not isinstance(name, str) or not SYMBOL.match(name):
        raise fail(f"must be a name of letters, digits and - _ . +, got {name!r}", f"{w}.name")
    slots = {key: _names(raw[key], fail, f"{w}.{key}") for key in SLOT_KEYS}
    states = []
    for key in STATE_KEYS:
        state = raw[key]
        if not isinstance(state, dict) or "relations" not in state:
            raise fail("must be an object with a 'relations' list", f"{w}.{key}")
        rels = state["relations"]
        if not isinstance(rels, list):
            raise fail("must be a list of relations", f"{w}.{key}.relations")
        states.append(
            frozenset(
                table.from_json(_relation(r, fail, f"{w}.{key}.relations[{k}]"))
                for k, r in enumerate(rels)
            )
        )
    return Operation(i, name, operation, slots["base"], slots["target"], slots["special"],
                     states[0], states[1])


def _names(value: Any, fail, where: str) -> tuple[str, ...]:
    """A list of object names."""
    if not isinstance(value, list) or not all(isinstance(v, str) and SYMBOL.match(v)
                                              for v in value):
        raise fail("must be a list of object names", where)
    return tuple(value)


def _relation(raw: Any, fail, where: str) -> list[Any]:
    """Check ``[type, subject, object(s), {"at": [x, y, z], "wrt": name}?]``."""
    shape = 'a relation is [type, subject, object(s), {"at": [x, y, z], "wrt": name}?]'
    if not isinstance(raw, list) or len(raw) not in (3, 4):
        raise fail(shape, where)
    for k, what in ((0, "type"), (1, "subject")):
        if not isinstance(raw[k], str) or not SYMBOL.match(raw[k]):
            raise fail(f"the relation's {what} must be a name, got {raw[k]!r}", where)
    obj = raw[2]
    objs = obj if isinstance(obj, list) else [obj]
    if not objs or not all(isinstance(o, str) and SYMBOL.match(o) for o in objs):
        raise fail(f"the relation's object must be a name or a list of names, got {obj!r}", where)
    if len(raw) == 4:
        meta = raw[3]
        if not isinstance(meta, dict) or set(meta) - {"at", "wrt"}:
            raise fail('the fourth item must be {"at": [x, y, z], "wrt": name}', where)
        at = meta.get("at")
        if "at" in meta and not (
            isinstance(at, list)
            and len(at) == 3
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c)
                    for c in at)
        ):
            raise fail(f"'at' must be [x, y, z] in mm, got {at!r}", where)
        wrt = meta.get("wrt")
        if "wrt" in meta and not (isinstance(wrt, str) and SYMBOL.match(wrt)):
            raise fail(f"'wrt' must be an object name, got {wrt!r}", where)
    return raw
