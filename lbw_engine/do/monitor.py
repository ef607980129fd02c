"""Execution monitoring and local repair (Sec. IX-C2, the paper's proposal for failures).

Pure logic; the caller measures. The robot's work is cut into units, one per
ACHIEVE (the operator that achieves one taught support relation, Fig. 15).
After each unit the measured state is compared with the state the plan's trace
expects after it (the same comparison as the final verification,
``verification.verify``); a difference is a detection. A repair matches the
measured state against the plan again (Sec. VII-A) — plan objects are named by
shape, nearest to where the trace expects them, and a missing one may be
replaced by a spare of its shape — and re-traces, in plan order, the units
whose effects are undone (an object off its goal, and everything the plan puts
on it) together with the units not yet done.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace

from lbw_engine.do.clearing import table_spots
from lbw_engine.do.matching import Measured
from lbw_engine.do.placement import occupies
from lbw_engine.do.plan import Plan, Relation, action_names, parents
from lbw_engine.do.tracing import TracedOp
from lbw_engine.do.verification import ObjectState
from lbw_engine.errors import TaskFailed
from lbw_engine.model.env import Body, EnvModel
from lbw_engine.model.geometry import TABLE, Vec, footprints_meet
from lbw_engine.rules import RuleSet

UNIT_CLASS = "ACHIEVE"  # plan.json's class of the operator a unit executes
SPARE_PREFIX = "unused:"
HIDDEN_MM = 5.0  # a block whose top is no lower than this under another's may hide it


@dataclass
class Unit:
    """One ACHIEVE as executed: its traced operations and the state expected after it."""

    operator: str
    ops: list[TracedOp]
    expected: dict[str, Vec] = field(default_factory=dict)
    supports: dict[str, tuple[str, tuple[str, ...]]] = field(default_factory=dict)

    @property
    def commands(self) -> list:
        """The unit's manipulator commands, in order."""
        return [c for op in self.ops for c in op.commands]

    @property
    def focus(self) -> str | None:
        """The object the unit moves (its first operation's focus)."""
        return next((op.focus for op in self.ops if op.focus), None)


def unit_of(plan: Plan) -> dict[str, str]:
    """Operator -> the ACHIEVE that contains it (itself for an ACHIEVE; else itself)."""
    parent = parents(plan)
    out = {}
    for name in plan.operators:
        at = name
        while at in parent and plan.operators[at].cls != UNIT_CLASS:
            at = parent[at]
        out[name] = at if plan.operators[at].cls == UNIT_CLASS else name
    return out


def units(plan: Plan, ops: Sequence[TracedOp], snapshots: Mapping[str, tuple]) -> list[Unit]:
    """Consecutive traced operations grouped by their ACHIEVE, with expected states."""
    owner = unit_of(plan)
    out: list[Unit] = []
    for op in ops:
        name = owner.get(op.operator, op.operator)
        if not out or out[-1].operator != name:
            out.append(Unit(name, []))
        out[-1].ops.append(op)
    for u in out:
        if u.operator in snapshots:
            u.expected, u.supports = snapshots[u.operator]
    return out


def pair_by_shape(expected: Mapping[str, Vec], shape_of: Mapping[str, str],
                  measured: Sequence[Measured], gate: float = math.inf,
                  taken: Iterable[int] = ()) -> dict[str, int]:
    """Name measurements by plan object: same shape, nearest pairs first, within ``gate`` mm.

    Measurements in ``taken`` are already named.
    """
    used = set(taken)
    pairs = sorted((d, n, i) for n in expected for i, m in enumerate(measured)
                   if i not in used and m.shape == shape_of[n]
                   and (d := math.dist(m.position, expected[n])) <= gate)
    named: dict[str, int] = {}
    for _, n, i in pairs:
        if n not in named and i not in used:
            named[n] = i
            used.add(i)
    return named


def detections(unit: Unit, mismatches: Sequence[dict], t: float) -> list[dict]:
    """execution.json ``monitor.detections`` records for one unit's mismatches."""
    return [{"operator": unit.operator, "object": m["object"], "expected": m["expected"],
             "observed": m["measured"], "t": round(t, 2), "kind": m["kind"]}
            for m in mismatches]


def in_the_way_of(todo: Sequence[Unit], sizes: Mapping[str, Vec],
                  spares: Mapping[str, ObjectState], t: float) -> list[dict]:
    """Detections of objects the plan does not use now lying where a unit still to do puts
    its object (helper round 19, r77: a post slid onto a cube's goal spot after the first
    unit; nothing the plan uses was off, so nothing was re-traced, and the cube was set
    down on the post). A re-trace sets them aside first, as it does at the start."""
    out = []
    for u in todo:
        goal = u.expected.get(u.focus) if u.focus is not None else None
        if goal is None:
            continue
        out += [{"operator": u.operator, "object": name, "expected": "elsewhere",
                 "observed": [round(float(v), 1) for v in st.position], "t": round(t, 2),
                 "kind": "in the way"}
                for name, st in spares.items()
                if occupies(goal, sizes[u.focus], st.position, st.size)]
    return out


def undone(done: Sequence[Unit], wrong: set[str], plan_supports: Mapping[str, tuple]
           ) -> list[Unit]:
    """Done units whose effect is gone: a wrong object's last placing unit, and every
    unit placing an object the plan rests (directly or not) on one of those."""
    bad = set(wrong)
    grew = True
    while grew:  # what the plan stacks on a displaced or fallen object must be redone too
        grew = False
        for name, (_, sup) in plan_supports.items():
            if name not in bad and bad & set(sup):
                bad.add(name)
                grew = True
    last: dict[str, Unit] = {}
    for u in done:
        if u.focus is not None:
            last[u.focus] = u
    return [u for u in done if u.focus in bad and last.get(u.focus) is u]


def hidden_under(missing: Iterable[str], expected: Mapping[str, Vec],
                 sizes: Mapping[str, Vec], measured: Sequence[Measured]) -> dict[str, Vec]:
    """Of the plan objects the cameras did not find, those that may lie hidden where the
    trace expects them: a measured block over that spot, its top above theirs (a beam
    fallen across a pillar, a tower whose base was slid from under it: helper round 21,
    f02, f12, f13). Each is taken to be there, so the repair moves what lies over it and
    looks again; it is not declared gone while something covers it."""
    out = {}
    for name in missing:
        at = expected.get(name)
        if at is not None and any(
                footprints_meet(at, sizes[name], m.position, m.size, tol=0.0)
                and m.position[2] + m.size[2] / 2 >= at[2] + sizes[name][2] / 2 - HIDDEN_MM
                for m in measured):
            out[name] = at
    return out


def remodel(rules: RuleSet, shapes: Mapping[str, Sequence[float]], shape_of: Mapping[str, str],
            states: Mapping[str, ObjectState], spares: Sequence[int],
            measured: Sequence[Measured], home: Vec, hidden: Mapping[str, Vec] | None = None
            ) -> EnvModel:
    """The environment model of the measured state (Sec. VII-A, matched again).

    A plan object the cameras no longer see is where ``hidden`` says it may lie under
    another block (``hidden_under``), or takes a spare of its shape (an object the plan
    does not use); with neither the task cannot be done.
    """
    bodies: dict[str, Body] = {}
    free = list(spares)
    for name, shape in shape_of.items():
        st = states.get(name)
        if st is None and hidden and name in hidden:
            st = ObjectState(tuple(hidden[name]), tuple(shapes[shape]))
        if st is None:
            k = next((i for i in free if measured[i].shape == shape), None)
            if k is None:
                raise TaskFailed(f"'{name}' (shape {shape}) is gone and the workspace has no "
                                 f"spare {shape} to replace it")
            free.remove(k)
            st = ObjectState(tuple(measured[k].position), tuple(measured[k].size))
        bodies[name] = Body(shape, tuple(shapes[shape]), tuple(st.position))
    for k in free:
        m = measured[k]
        bodies[f"unused-{m.shape}-{k}"] = Body(m.shape, tuple(m.size), tuple(m.position), False)
    return EnvModel.measured(rules, bodies, home)


ASIDE_EDGE_MM = 30.0  # a set-aside block is kept this far in from the table's edges
ASIDE_CLEAR_MM = (45.0, 25.0, 12.0)  # room for the fingers beside a set-aside block, tried in turn


def in_the_way(redo: Sequence[Unit], goals: Mapping[str, Vec], model: EnvModel
               ) -> list[str]:
    """Redone objects lying where an earlier redone unit must put its object (a rider
    that fell when its support was slid away lies on the support's spot)."""
    out: list[str] = []
    for k, u in enumerate(redo):
        f = u.focus
        if f is None or f not in goals:
            continue
        size = model.bodies[f].size
        for later in redo[k + 1:]:
            x = later.focus
            if x and x not in out and footprints_meet(goals[f], size, model.bodies[x].position,
                                                      model.bodies[x].size, tol=0.0):
                out.append(x)
    return out


def aside_spot(name: str, model: EnvModel, keep_clear: Mapping[str, Vec]) -> Vec:
    """A free table spot for ``name``, nearest to where it lies: clear of every body and
    of every plan object's goal (``keep_clear``)."""
    size = model.bodies[name].size
    here = model.bodies[name].position
    others = [(b.position, b.size) for n, b in model.bodies.items() if n != name]
    others += [(g, model.bodies[n].size) for n, g in keep_clear.items() if n in model.bodies]
    # a wide block may find no spot with the full room: less, down to a finger's width
    # (helper round 22, f02: a 160 x 120 table top, its four legs' goals kept clear)
    for clear in ASIDE_CLEAR_MM:
        for spot in table_spots(here, size, edge=ASIDE_EDGE_MM):
            if not any(footprints_meet(spot, size, p, s, tol=-clear) for p, s in others):
                return spot
    raise TaskFailed(f"no free spot on the table to set '{name}' aside")


def aside_plan(plan: Plan, unit: str, name: str, spot: Vec, support_type: str) -> Plan:
    """The plan with ``unit`` putting ``name`` on the table at ``spot`` instead (a set-aside
    made of the unit's own operations, so Table IX expands it as usual)."""
    inside = {unit}
    todo = [unit]
    while todo:
        for child in action_names(plan.operators[todo.pop()].plot):
            if child in plan.operators and child not in inside:
                inside.add(child)
                todo.append(child)
    rel = Relation(support_type, name, (TABLE,), False, tuple(spot), TABLE)
    kinds = {r.type for op in plan.operators.values() for r in op.sc_plus
             if r.subject == name and r.at is not None}  # how the plan puts it somewhere
    ops = dict(plan.operators)
    for op_name in inside:
        op = ops[op_name]
        placed = any(r.subject == name and r.type in kinds for r in op.sc_plus)
        # Keep what does not place ``name`` and does not rest on it (co-supports).
        plus = [r for r in op.sc_plus if not (r.subject == name and r.type in kinds)
                and name not in r.objects]
        ops[op_name] = replace(op, sc_plus=tuple(plus + [rel] * placed))
    return replace(plan, operators=ops)
