"""Reading plan.json (design.md "Plan") for execution, with checks that name the place.

Only what execution needs is checked: the root exists, every operator has a
class and a well-formed plot, plots reference operators or recognized
operation leaves, no operator contains itself, and relations have the form
``[type, subject, object(s), {"at": [x, y, z], "wrt": name}?]``.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError, read_input

PLOT_HEADS = ("$sequence", "$parallel", "$action")
SLOTS = ("base", "target", "special")
RELATION_SLOTS = ("sc_plus", "sc_minus", "si", "sp")
# A recognized operation's name is its operation in lower case plus a number (pick01).
LEAF_NAME = re.compile(r"([a-z][a-z-]*?)-?(\d+)\Z")


@dataclass(frozen=True)
class Relation:
    """A relation [type, subject, object(s)] with optional ``:at ... :wrt`` coordinates."""

    type: str
    subject: str
    objects: tuple[str, ...]
    multiple: bool = False  # the object was a list (on-multiple)
    at: tuple[float, float, float] | None = None
    wrt: str | None = None


@dataclass(frozen=True)
class Operator:
    """One upper-level operator (BUILD, PACHIEVE, ACHIEVE, FETCH, PUT, FAKE)."""

    name: str
    cls: str
    slots: dict[str, tuple[str, ...]]
    sc_plus: tuple[Relation, ...]
    sc_minus: tuple[Relation, ...]
    plot: Any
    si: tuple[Relation, ...] = ()  # invariant relations (Fig. 14: riders of a carried plank)


@dataclass(frozen=True)
class Plan:
    """A loaded plan: root, operators, and the optional taught objects."""

    root: str
    operators: dict[str, Operator]
    objects: dict[str, dict] | None = None
    leaf_operations: dict[str, str] = field(default_factory=dict)  # leaf name -> operation
    file: str = "<plan>"


def load(path: str | Path) -> Plan:
    """Read and check a plan.json file."""
    path = Path(path)
    text = read_input(path, expected="a plan.json file")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"invalid JSON: {exc.msg}", file=path, line=exc.lineno) from None
    return parse(doc, str(path))


def parse(doc: Any, file: str = "<plan>") -> Plan:
    """Check a plan.json document and build the Plan."""
    def fail(msg: str, where: str) -> InputError:
        return InputError(msg, file=file, where=where)

    if not isinstance(doc, dict) or "root" not in doc or "operators" not in doc:
        raise fail("a plan must be an object with 'root' and 'operators'", "")
    ops_raw = doc["operators"]
    if not isinstance(ops_raw, dict):
        raise fail("must be an object of operator name → operator", "operators")
    operators = {name: _operator(name, body, fail) for name, body in ops_raw.items()}
    if doc["root"] not in operators:
        raise fail(f"root operator '{doc['root']}' is not among the operators", "root")
    objects = doc.get("objects")
    if objects is not None:
        _objects(objects, fail)
    leaves: dict[str, str] = {}
    _check_plot_refs(doc["root"], operators, leaves, fail, [])
    return Plan(doc["root"], operators, objects, leaves, file)


def _operator(name: str, body: Any, fail) -> Operator:
    """One operator entry."""
    w = f"operators.{name}"
    if not isinstance(body, dict) or not isinstance(body.get("class"), str):
        raise fail("must be an object with a 'class'", w)
    if "plot" not in body:
        raise fail("missing 'plot'", w)
    slots = {}
    for s in SLOTS:
        v = body.get(s, [])
        if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
            raise fail("must be a list of object names", f"{w}.{s}")
        slots[s] = tuple(v)
    rels = {}
    for s in RELATION_SLOTS:
        v = body.get(s, [])
        if not isinstance(v, list):
            raise fail("must be a list of relations", f"{w}.{s}")
        rels[s] = tuple(_relation(r, fail, f"{w}.{s}[{i}]") for i, r in enumerate(v))
    _check_plot_shape(body["plot"], fail, f"{w}.plot")
    return Operator(name, body["class"], slots, rels["sc_plus"], rels["sc_minus"], body["plot"],
                    rels["si"])


def _relation(r: Any, fail, where: str) -> Relation:
    """[type, subject, object(s), {at, wrt}?]."""
    if not isinstance(r, list) or len(r) not in (3, 4):
        raise fail("a relation is [type, subject, object(s), {\"at\", \"wrt\"}?]", where)
    rtype, subj, obj = r[0], r[1], r[2]
    if not isinstance(rtype, str) or not isinstance(subj, str):
        raise fail("relation type and subject must be names", where)
    multiple = isinstance(obj, list)
    objs = tuple(obj) if multiple else (obj,)
    if not objs or not all(isinstance(o, str) for o in objs):
        raise fail("relation object must be a name or a non-empty list of names", where)
    at = wrt = None
    if len(r) == 4:
        meta = r[3]
        if not isinstance(meta, dict) or set(meta) - {"at", "wrt"}:
            raise fail("the fourth item must be {\"at\": [x, y, z], \"wrt\": name}", where)
        if "at" in meta:
            a = meta["at"]
            if (not isinstance(a, list) or len(a) != 3
                    or not all(isinstance(c, (int, float)) and not isinstance(c, bool)
                               for c in a)):
                raise fail("'at' must be [x, y, z] in mm", where)
            at = tuple(float(c) for c in a)
        if "wrt" in meta:
            if not isinstance(meta["wrt"], str):
                raise fail("'wrt' must be an object name", where)
            wrt = meta["wrt"]
    return Relation(rtype, subj, objs, multiple, at, wrt)


def _check_plot_shape(plot: Any, fail, where: str) -> None:
    """PLOT = ["$sequence", PLOT...] | ["$parallel", PLOT...] | ["$action", NAME]."""
    if not isinstance(plot, list) or not plot or plot[0] not in PLOT_HEADS:
        raise fail("a plot is [\"$sequence\"|\"$parallel\", PLOT...] or [\"$action\", NAME]",
                   where)
    if plot[0] == "$action":
        if len(plot) != 2 or not isinstance(plot[1], str):
            raise fail("an action plot is [\"$action\", NAME]", where)
        return
    for i, sub in enumerate(plot[1:], 1):
        _check_plot_shape(sub, fail, f"{where}[{i}]")


def _check_plot_refs(name: str, ops: dict[str, Operator], leaves: dict[str, str], fail,
                     path: list[str]) -> None:
    """Operators do not contain themselves; leaf names read as operation + number."""
    if name in path:
        raise fail(f"operator '{name}' contains itself ({' → '.join([*path, name])})",
                   f"operators.{name}.plot")
    for leaf in action_names(ops[name].plot):
        if leaf in ops:
            _check_plot_refs(leaf, ops, leaves, fail, [*path, name])
            continue
        m = LEAF_NAME.match(leaf)
        if not m:
            raise fail(f"'{leaf}' is neither an operator nor a recognized operation name "
                       "(operation + number, e.g. pick01)", f"operators.{name}.plot")
        leaves[leaf] = m.group(1).upper()


def action_names(plot: Any) -> list[str]:
    """The $action names of a plot in listed (depth-first) order."""
    if plot[0] == "$action":
        return [plot[1]]
    return [n for sub in plot[1:] for n in action_names(sub)]


def _objects(objects: Any, fail) -> None:
    """The optional top-level objects: {name: {shape, position?}}."""
    if not isinstance(objects, dict):
        raise fail("must be an object of name → {shape, position}", "objects")
    for name, o in objects.items():
        if not isinstance(o, dict) or not isinstance(o.get("shape"), str):
            raise fail("must be an object with a 'shape'", f"objects.{name}")
        p = o.get("position")
        if p is not None and (not isinstance(p, list) or len(p) != 3):
            raise fail("'position' must be [x, y, z]", f"objects.{name}.position")
