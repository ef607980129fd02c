"""Reading actions.json (design.md "Recognized actions") for plan analysis.

Only what analysis needs is required, so hand-written files work: per operation
``operation``, ``base``, ``target``, ``special``, ``initial_state.relations``
and ``final_state.relations``. ``name`` is optional; a missing one becomes the
operation in lower case plus a per-operation counter (``reach01``), the form of
Fig. 12. The file is read as strictly as a scenario: unknown keys are errors,
the optional keys the recognizer writes are type-checked, and (when the rules'
hold relation is given) a demonstration must end with the hand empty. Every
problem is an InputError naming the file and the key path.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.guard import clip, json_document, known_keys, read_text, shorten
from lbw_engine.understand.gcpause import without_gc
from lbw_engine.understand.relations import Rel, RelationTable

# Names must be writable in the plot notation of plan.txt (rules/plot.lark NAME).
SYMBOL = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+\-]*\Z")
STATE_KEYS = ("initial_state", "final_state")
SLOT_KEYS = ("base", "target", "special")
# The keys of design.md "Recognized actions": required, and optional (checked
# when present; written by `lbw watch`).
TOP_KEYS = ("operations", "objects", "repairs")
OP_REQUIRED = ("operation", *SLOT_KEYS, *STATE_KEYS)
OP_NAMES = ("name", "motion", "initial_event", "final_event")  # a name or null
OP_TIMES = ("t_start", "t_end")  # seconds or null
OP_KEYS = (*OP_REQUIRED, *OP_NAMES, *OP_TIMES, "fine")
FINE_KEYS = ("operation", *OP_TIMES)
REPAIR_KEYS = ("at", "was", "now", "why")


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


def load_actions(path: str | Path, table: RelationTable,
                 hold_relation: str | None = None) -> ActionSequence:
    """Read and check an actions.json file; relations are interned into ``table``."""
    return parse_actions(read_actions(path), table, str(path), hold_relation)


def read_actions(path: str | Path) -> Any:
    """The JSON document of an actions.json file (not yet checked: ``parse_actions``)."""
    path = Path(path)
    return json_document(read_text(path, expected="an actions.json file"), path)


@without_gc
def parse_actions(doc: Any, table: RelationTable, file: str = "<actions>",
                  hold_relation: str | None = None) -> ActionSequence:
    """Check an actions.json document and build the ActionSequence.

    ``hold_relation`` is the rules' relation of a hand holding an object
    (effects.yaml ``hold-relation``); given it, a sequence whose last final
    state still holds something is refused: no Fig. 15 template ends holding.
    """

    def fail(message: str, where: str | None = None) -> InputError:
        return InputError(message, file=file, where=where)

    if not isinstance(doc, dict) or "operations" not in doc:
        raise fail("an actions file must be a JSON object with an 'operations' list")
    known_keys(doc, TOP_KEYS, "", fail)
    raw_ops = doc["operations"]
    if not isinstance(raw_ops, list):
        raise fail("must be a list of operations", "operations")
    if not raw_ops:
        raise fail("the action sequence is empty: there is nothing to analyze", "operations")
    objects = doc.get("objects")
    if objects is not None:
        _objects(objects, fail)
    if "repairs" in doc:
        _repairs(doc["repairs"], fail)
    counters: dict[str, int] = {}
    seen: dict[str, str] = {}
    ops = []
    for i, raw in enumerate(raw_ops):
        op = _operation(i, raw, table, counters, fail)
        if op.name in seen:
            raise fail(f"duplicate operation name {shorten(op.name)} (also {seen[op.name]})",
                       f"operations[{i}].name")
        seen[op.name] = f"operations[{i}]"
        ops.append(op)
    if hold_relation is not None:
        _ends_empty(ops[-1], hold_relation, fail)
    return ActionSequence(file, tuple(ops), dict(objects) if objects is not None else None)


def _ends_empty(last: Operation, hold_relation: str, fail) -> None:
    """The demonstration ends with the hand empty (Fig. 15 templates end with a PUT)."""
    for rel in sorted(last.final, key=lambda r: (r.subject, r.objects)):
        if rel.type == hold_relation:
            held = " ".join(rel.objects)
            raise fail(f"the demonstration ends with {rel.subject} {hold_relation} {held}; "
                       "expected it to end with the hand empty",
                       f"operations[{last.index}].final_state.relations")


def _operation(i: int, raw: Any, table: RelationTable, counters: dict[str, int], fail) -> Operation:
    """One entry of ``operations``."""
    w = f"operations[{i}]"
    if not isinstance(raw, dict):
        raise fail("must be an object", w)
    for key in OP_REQUIRED:
        if key not in raw:
            raise fail(f"missing the required key {key!r}", w)
    known_keys(raw, OP_KEYS, w, fail)
    operation = raw["operation"]
    if not isinstance(operation, str) or not SYMBOL.match(operation):
        raise fail(f"must be an operation name, got {shorten(operation)}", f"{w}.operation")
    counters[operation] = counters.get(operation, 0) + 1
    name = raw.get("name", f"{operation.lower()}{counters[operation]:02d}")
    if not isinstance(name, str) or not SYMBOL.match(name):
        raise fail(f"must be a name of letters, digits and - _ . +, got {shorten(name)}",
                   f"{w}.name")
    _optional(raw, w, fail)
    slots = {key: _names(raw[key], fail, f"{w}.{key}") for key in SLOT_KEYS}
    states = []
    for key in STATE_KEYS:
        state = raw[key]
        if not isinstance(state, dict) or "relations" not in state:
            raise fail("must be an object with a 'relations' list", f"{w}.{key}")
        known_keys(state, ("relations", "positions"), f"{w}.{key}", fail)
        if "positions" in state:
            _positions(state["positions"], fail, f"{w}.{key}.positions")
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


def _optional(raw: dict, w: str, fail) -> None:
    """The keys the recognizer writes besides what analysis needs: typed when present."""
    for key in OP_NAMES:
        if raw.get(key) is not None and not isinstance(raw[key], str):
            raise fail(f"must be a name or null, got {shorten(raw[key])}", f"{w}.{key}")
    _times(raw, w, fail)
    fine = raw.get("fine", [])
    if not isinstance(fine, list):
        raise fail("must be a list of {operation, t_start, t_end}", f"{w}.fine")
    for k, sub in enumerate(fine):
        where = f"{w}.fine[{k}]"
        if not isinstance(sub, dict) or not isinstance(sub.get("operation"), str | None):
            raise fail("must be an object {operation, t_start, t_end}", where)
        known_keys(sub, FINE_KEYS, where, fail)
        _times(sub, where, fail)


def _times(raw: dict, w: str, fail) -> None:
    """``t_start`` / ``t_end``: seconds (>= 0) or null, the end not before the start."""
    for key in OP_TIMES:
        t = raw.get(key)
        if t is not None and (not _is_number(t) or t < 0):
            raise fail(f"must be a time in seconds (>= 0) or null, got {shorten(t)}",
                       f"{w}.{key}")
    if _is_number(raw.get("t_start")) and _is_number(raw.get("t_end")) and \
            raw["t_end"] < raw["t_start"]:
        raise fail(f"ends at {raw['t_end']} s, before it starts ({raw['t_start']} s)",
                   f"{w}.t_end")


def _is_number(value: Any) -> bool:
    """A JSON number (the reader has made sure it is finite)."""
    return isinstance(value, int | float) and not isinstance(value, bool)


def _point(value: Any) -> bool:
    """[x, y, z] in mm."""
    return isinstance(value, list) and len(value) == 3 and all(_is_number(c) for c in value)


def _positions(raw: Any, fail, where: str) -> None:
    """``positions``: object name -> [x, y, z]."""
    if not isinstance(raw, dict):
        raise fail("must be an object of name -> [x, y, z]", where)
    for name, p in raw.items():
        if not SYMBOL.match(name) or not _point(p):
            raise fail(f"must be [x, y, z] in mm, got {shorten(p)}",
                       f"{where}.{clip(name, 40)}")


def _objects(raw: Any, fail) -> None:
    """``objects``: name -> {shape, position} as the object-finder measured them."""
    if not isinstance(raw, dict):
        raise fail("must be an object of name -> {shape, position}", "objects")
    for name, obj in raw.items():
        where = f"objects.{clip(name, 40)}"
        if not SYMBOL.match(name) or not isinstance(obj, dict):
            raise fail("must be an object {shape, position} named by letters, digits and "
                       "- _ . +", where)
        known_keys(obj, ("shape", "position"), where, fail)
        if not isinstance(obj.get("shape"), str) or not _point(obj.get("position")):
            raise fail(f"needs a shape name and a position [x, y, z], got {shorten(obj)}",
                       where)


def _repairs(raw: Any, fail) -> None:
    """``repairs`` (design.md): [{at: INDEX, was: [...], now: [...], why: "..."}]."""
    if not isinstance(raw, list):
        raise fail("must be a list of {at, was, now, why}", "repairs")
    for k, rep in enumerate(raw):
        where = f"repairs[{k}]"
        if not isinstance(rep, dict):
            raise fail("must be an object {at, was, now, why}", where)
        known_keys(rep, REPAIR_KEYS, where, fail)
        at = rep.get("at")
        if isinstance(at, bool) or not isinstance(at, int) or at < 0:
            raise fail(f"'at' must be an operation index >= 0, got {shorten(at)}", where)
        if not all(isinstance(rep.get(key), list) for key in ("was", "now")) or \
                not isinstance(rep.get("why"), str):
            raise fail("needs 'was' and 'now' lists and a 'why' sentence", where)


def _names(value: Any, fail, where: str) -> tuple[str, ...]:
    """A list of object names."""
    if not isinstance(value, list) or not all(isinstance(v, str) and SYMBOL.match(v)
                                              for v in value):
        raise fail(f"must be a list of object names, got {shorten(value)}", where)
    return tuple(value)


def _relation(raw: Any, fail, where: str) -> list[Any]:
    """Check ``[type, subject, object(s), {"at": [x, y, z], "wrt": name}?]``."""
    shape = 'a relation is [type, subject, object(s), {"at": [x, y, z], "wrt": name}?]'
    if not isinstance(raw, list) or len(raw) not in (3, 4):
        raise fail(f"{shape}, got {shorten(raw)}", where)
    for k, what in ((0, "type"), (1, "subject")):
        if not isinstance(raw[k], str) or not SYMBOL.match(raw[k]):
            raise fail(f"the relation's {what} must be a name, got {shorten(raw[k])}", where)
    obj = raw[2]
    objs = obj if isinstance(obj, list) else [obj]
    if not objs or not all(isinstance(o, str) and SYMBOL.match(o) for o in objs):
        raise fail("the relation's object must be a name or a list of names, got "
                   f"{shorten(obj)}", where)
    if len(raw) == 4:
        meta = raw[3]
        if not isinstance(meta, dict) or set(meta) - {"at", "wrt"}:
            raise fail('the fourth item must be {"at": [x, y, z], "wrt": name}', where)
        if "at" in meta and not _point(meta["at"]):
            raise fail(f"'at' must be [x, y, z] in mm, got {shorten(meta['at'])}", where)
        wrt = meta.get("wrt")
        if "wrt" in meta and not (isinstance(wrt, str) and SYMBOL.match(wrt)):
            raise fail(f"'wrt' must be an object name, got {shorten(wrt)}", where)
    return raw
