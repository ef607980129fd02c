"""Reading plan.json (design.md "Plan") for execution, with checks that name the place.

The file is checked as strictly as a scenario: no unknown keys; the root
exists; every operator has a class of design.md and a well-formed plot; plots
reference operators or recognized operation leaves; no operator contains
itself and operators nest at most ``MAX_NESTING`` deep; ``next`` names
operators; relations have the form
``[type, subject, object(s), {"at": [x, y, z], "wrt": name}?]``.
"""

from __future__ import annotations

import re
from collections.abc import Collection
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.guard import clip, json_document, known_keys, read_text, shorten
from lbw_engine.rules.analysis import PLAN_CLASSES

PLOT_HEADS = ("$sequence", "$parallel", "$action")
SLOTS = ("base", "target", "special")
RELATION_SLOTS = ("sc_plus", "sc_minus", "si", "sp")
TOP_KEYS = ("root", "operators", "objects")
OPERATOR_KEYS = ("class", *SLOTS, *RELATION_SLOTS, "plot", "next")
# Operators inside operators: a learned plan nests a few levels (a tower of n
# blocks about n); far deeper is no plan of a 600 x 400 x 300 mm workspace.
MAX_NESTING = 100
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
    return parse(json_document(read_text(path, expected="a plan.json file"), path), str(path))


def parse(doc: Any, file: str = "<plan>") -> Plan:
    """Check a plan.json document and build the Plan."""
    def fail(msg: str, where: str) -> InputError:
        return InputError(msg, file=file, where=where)

    if not isinstance(doc, dict) or "root" not in doc or "operators" not in doc:
        raise fail("a plan must be an object with 'root' and 'operators'", "")
    known_keys(doc, TOP_KEYS, "", fail)
    ops_raw = doc["operators"]
    if not isinstance(ops_raw, dict):
        raise fail("must be an object of operator name → operator", "operators")
    operators = {name: _operator(name, body, fail) for name, body in ops_raw.items()}
    root = doc["root"]
    if not isinstance(root, str) or root not in operators:
        raise fail(f"root operator {shorten(root)} is not among the operators", "root")
    for name, body in ops_raw.items():
        for i, nxt in enumerate(body.get("next", [])):
            if nxt not in operators:
                raise fail(f"{shorten(nxt)} is not an operator of the plan",
                           f"operators.{clip(name)}.next[{i}]")
    objects = doc.get("objects")
    if objects is not None:
        _objects(objects, fail)
    leaves: dict[str, str] = {}
    _check_plot_refs(root, operators, leaves, fail)
    return Plan(root, operators, objects, leaves, file)


def _operator(name: str, body: Any, fail) -> Operator:
    """One operator entry."""
    w = f"operators.{clip(name)}"
    if not isinstance(body, dict) or "class" not in body:
        raise fail("must be an object with a 'class'", w)
    known_keys(body, OPERATOR_KEYS, w, fail)
    if body["class"] not in PLAN_CLASSES:
        raise fail(f"class {shorten(body['class'])} is not one of {', '.join(PLAN_CLASSES)}",
                   f"{w}.class")
    if "plot" not in body:
        raise fail("missing 'plot'", w)
    slots = {}
    for s in (*SLOTS, "next"):
        v = body.get(s, [])
        if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
            raise fail(f"must be a list of names, got {shorten(v)}", f"{w}.{s}")
        slots[s] = tuple(v)
    del slots["next"]
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
    if len(plot) < 2:
        raise fail(f"a {plot[0]} plot holds at least one PLOT (rules/plot.lark: plot+)", where)
    for i, sub in enumerate(plot[1:], 1):
        _check_plot_shape(sub, fail, f"{where}[{i}]")


def _check_plot_refs(root: str, ops: dict[str, Operator], leaves: dict[str, str],
                     fail) -> None:
    """Operators do not contain themselves and nest at most MAX_NESTING deep; leaf names
    read as operation + number. Depth first without recursion (a plan is user data)."""
    done: set[str] = set()
    path: list[str] = [root]
    pending: list[list[str]] = [list(reversed(action_names(ops[root].plot)))]
    while pending:
        if not pending[-1]:
            done.add(path.pop())
            pending.pop()
            continue
        leaf, name = pending[-1].pop(), path[-1]
        if leaf in ops:
            if leaf in path:
                cycle = " → ".join([*path[path.index(leaf):], leaf])
                raise fail(f"operator {shorten(leaf)} contains itself ({clip(cycle, 120)})",
                           f"operators.{clip(name)}.plot")
            if leaf in done:  # a plan is a tree: each operator has one place in it
                raise fail(f"operator {shorten(leaf)} is in the plots twice",
                           f"operators.{clip(name)}.plot")
            if len(path) >= MAX_NESTING:
                raise fail(f"operators nest more than {MAX_NESTING} deep",
                           f"operators.{clip(name)}.plot")
            path.append(leaf)
            pending.append(list(reversed(action_names(ops[leaf].plot))))
            continue
        m = LEAF_NAME.match(leaf)
        if not m:
            raise fail(f"{shorten(leaf)} is neither an operator nor a recognized operation name "
                       "(operation + number, e.g. pick01)", f"operators.{clip(name)}.plot")
        if leaf in leaves:  # one recognized action, done once
            raise fail(f"action {shorten(leaf)} is in the plots twice",
                       f"operators.{clip(name)}.plot")
        leaves[leaf] = m.group(1).upper()


def action_names(plot: Any) -> list[str]:
    """The $action names of a plot in listed (depth-first) order."""
    if plot[0] == "$action":
        return [plot[1]]
    return [n for sub in plot[1:] for n in action_names(sub)]


def parents(plan: Plan) -> dict[str, str]:
    """Operator -> the operator whose plot holds it."""
    return {child: name for name, op in plan.operators.items()
            for child in action_names(op.plot) if child in plan.operators}


def placed(plan: Plan, support: Collection[str]) -> set[str]:
    """The objects some operator gives a new ``support`` relation (SC+): those the plan
    moves; every other object stays where it starts."""
    return {r.subject for op in plan.operators.values() for r in op.sc_plus
            if r.type in support}


def _objects(objects: Any, fail) -> None:
    """The optional top-level objects: {name: {shape, position?}}."""
    if not isinstance(objects, dict):
        raise fail("must be an object of name → {shape, position}", "objects")
    for name, o in objects.items():
        where = f"objects.{clip(name)}"
        if not isinstance(o, dict) or not isinstance(o.get("shape"), str):
            raise fail("must be an object with a 'shape'", where)
        known_keys(o, ("shape", "position"), where, fail)
        p = o.get("position")
        if p is not None and (not isinstance(p, list) or len(p) != 3 or not all(
                isinstance(c, int | float) and not isinstance(c, bool) for c in p)):
            raise fail(f"'position' must be [x, y, z], got {shorten(p)}", f"{where}.position")
