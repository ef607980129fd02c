"""Blocks that start stacked on one the plan picks: set them aside first.

The plan's objects may start stacked in the execution workspace where they lay
apart when taught (design.md: "stacks in the teach or execute workspace").
Picking a block carries whatever rests on it (the plank of Fig. 14), which is
what the plan means only for blocks it put there itself, or whose riding it
recorded (an operator's SI). Any other rider — a plan object still to be put
where the plan wants it, or an object the plan does not use — is first put on
a free spot of the table, top-most first, by commands.yaml's ``set-aside``
steps; then the pick goes on as planned. The paper leaves execution repairs
open (Sec. IX-C2); this is the least one that keeps the plan's meaning.

A free spot is a table spot where the rider and the open jaws around it meet
nothing, away from where the plan will build (each taught placement in world
coordinates, grown by ``BUILD_MARGIN_MM``, or by less where nothing that far is
free: ``MARGINS_MM``), nearest the rider first.

The same steps put down a block that no one way of closing the jaws can both
pick up and put where the plan wants it (``plan_regrasp``): it is set down on a
free spot where it can be let go one way and taken again the other.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from lbw_engine.do import grasp, jaws
from lbw_engine.do.plan import Plan, Relation, parents, placed
from lbw_engine.errors import TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import TABLE, TABLE_X, TABLE_Y, Vec, overlap
from lbw_engine.rules.commands import CommandRules

EDGE_MM = 12.0  # kept from the table's edge
SKY_MM = 400.0  # the column kept free above a set-aside spot reaches this high
GRID_MM = 10.0  # spacing of candidate spots
BUILD_MARGIN_MM = 60.0  # room kept around the places the plan will fill
# ... less when nothing is free so far from them, never into them: a 200 x 130 plate
# lying where its walls go found no spot 60 mm clear of the walls and of its own place
# on them (helper round 11, v109m: "the spot is occupied by 'p'")
# (the last lets it stand flush against a build site: 109's plate fits only there, 2 mm
# from its own site; the jaws of a place there are not checked in advance)
MARGINS_MM = (BUILD_MARGIN_MM, BUILD_MARGIN_MM / 2, 0.0)


@dataclass(frozen=True)
class SetAside:
    """One rider put aside: its name, where it stood, where it goes, its grip."""

    name: str
    start: Vec
    spot: Vec
    axis: int
    offset: float


def unplanned_riders(plan: Plan, focus: str, rules: CommandRules,
                     model: EnvModel, operator: str | None = None) -> list[str]:
    """What rests on ``focus`` that the plan did not put there nor means to carry, and
    everything above it, top first."""
    riders = model.supported_by(focus)
    stack = {focus, *riders}
    # riding is what the operator picking ``focus`` (or one it is part of) keeps invariant;
    # another operator's SI says where a block goes later, not that it rides now (a
    # tower taught cube on cube: its cubes stacked on the slab rode along, e08b)
    ops = _enclosing(plan, operator) if operator in plan.operators else plan.operators
    meant = {r.subject for name in ops for r in plan.operators[name].si
             if r.type in rules.support_relations and stack & set(r.objects)}

    unplanned = [r for r in riders if r not in model.placed and r not in meant]
    if not unplanned:
        return []
    # whatever stands higher goes first, meant to ride or not: it cannot stay up while
    # the block under it is taken away
    lowest = min(model.bodies[r].position[2] for r in unplanned)
    return top_first([r for r in riders if model.bodies[r].position[2] >= lowest], model)


def top_first(names: list[str], model: EnvModel) -> list[str]:
    """``names`` by height, the highest first: the order a stack comes down in. The order
    of the support relations is no stacking order (three cubes on a slab: the middle one
    was set aside first and carried the top one along, helper round 6's e08b)."""
    return sorted(names, key=lambda n: -model.bodies[n].position[2])


def _enclosing(plan: Plan, name: str) -> list[str]:
    """Operator ``name`` and every operator whose plot holds it, innermost first."""
    parent = parents(plan)
    out = [name]
    while out[-1] in parent and parent[out[-1]] not in out:
        out.append(parent[out[-1]])
    return out


def plan_set_aside(plan: Plan, name: str, rules: CommandRules, model: EnvModel,
                   keep_clear: Sequence[tuple[Vec, Vec]] = ()) -> SetAside | None:
    """Where and how to put ``name`` down on the table, or None if nowhere is free;
    ``keep_clear``: more boxes (centre, size) it must not meet there.
    TaskFailed: no grip takes it."""
    body = model.bodies[name]
    if not jaws.fitting_axes(body.size, rules):
        raise TaskFailed(jaws.too_wide(name, body.size, rules) + ": it cannot be set aside")
    axis, off = grasp.choose(name, body.position, rules, model, strict=False)
    for spot, avoid in _candidates(plan, name, rules, model):
        if _clear(name, spot, axis, off, rules, model, [*avoid, *keep_clear]):
            return SetAside(name, body.position, spot, axis, off)
    return None


def plan_regrasp(plan: Plan, name: str, picks: list[tuple[int, float]],
                 places: list[tuple[int, float]], rules: CommandRules,
                 model: EnvModel) -> SetAside | None:
    """Where to put ``name`` down to take it again another way (grasp.NoCommonGrip): a
    free table spot where one of ``picks`` can let go of it and one of ``places`` can
    take it up, nearest it first."""
    body = model.bodies[name]
    for spot, avoid in _candidates(plan, name, rules, model):
        for axis, off in picks:
            if _clear(name, spot, axis, off, rules, model, avoid) and any(
                    jaws.blocker(name, spot, a, o, rules, model) is None for a, o in places):
                return SetAside(name, body.position, spot, axis, off)
    return None


def _candidates(plan: Plan, name: str, rules: CommandRules, model: EnvModel
                ) -> Iterator[tuple[Vec, list[tuple[Vec, Vec]]]]:
    """Table spots for ``name``, nearest it first, each with the build sites it must keep
    clear of: grown by each of MARGINS_MM in turn."""
    body = model.bodies[name]
    spots = table_spots(body.position, body.size)
    for margin in MARGINS_MM:
        avoid = _build_sites(plan, rules, model, margin)
        for spot in spots:
            yield spot, avoid


def support_on_table(name: str, rules: CommandRules) -> Relation:
    """The relation that says ``name`` now rests on the table (the single support role)."""
    return Relation(rules.support_relations[0], name, (TABLE,))


def table_spots(start: Vec, size: Vec, edge: float = EDGE_MM) -> list[Vec]:
    """Candidate table spots for a box of ``size`` (``edge`` mm in from the table's
    edges, on a grid), nearest ``start`` first: every set-aside searches these."""
    hx, hy = size[0] / 2 + edge, size[1] / 2 + edge
    out = [(x, y, size[2] / 2) for x in _steps(TABLE_X[0] + hx, TABLE_X[1] - hx)
           for y in _steps(TABLE_Y[0] + hy, TABLE_Y[1] - hy)]
    return sorted(out, key=lambda p: (p[0] - start[0]) ** 2 + (p[1] - start[1]) ** 2)


def _steps(lo: float, hi: float) -> list[float]:
    """``lo`` to ``hi`` by GRID_MM, and ``hi`` itself: a wide plate fits only against the
    table's far edge, 6 mm past the last grid row (helper round 11, 109)."""
    out = []
    v = lo
    while v <= hi:
        out.append(v)
        v += GRID_MM
    return out + [hi] if out and hi - out[-1] > 1e-6 else out


def _build_sites(plan: Plan, rules: CommandRules, model: EnvModel,
                 margin: float = BUILD_MARGIN_MM) -> list[tuple[Vec, Vec]]:
    """Boxes around the taught placements in world coordinates, grown by ``margin``: the
    plan builds there. A placement relative to a block no operator moves is where that
    block stands now (a table place kept beside a stack that stays, anchor_table_places)."""
    moved = placed(plan, rules.support_relations)
    out = []
    for op in plan.operators.values():
        for r in op.sc_plus:
            if r.type not in rules.support_relations or r.at is None or \
                    r.subject not in model.bodies:
                continue
            if r.wrt in (None, TABLE):
                at = r.at
            elif r.wrt in model.bodies and r.wrt not in moved:
                at = tuple(a + b for a, b in zip(r.at, model.bodies[r.wrt].position,
                                                 strict=True))
            else:
                continue
            s = model.bodies[r.subject].size
            grow = 2 * margin
            out.append(((at[0], at[1], 150.0), (s[0] + grow, s[1] + grow, 300.0)))
    return out


def _clear(name: str, spot: Vec, axis: int, off: float, rules: CommandRules,
           model: EnvModel, avoid: list[tuple[Vec, Vec]]) -> bool:
    """Can ``name`` stand at ``spot``, the jaws around it, away from the build sites?"""
    size = model.bodies[name].size
    ignore = jaws.moving(name, model)
    if any(overlap(spot, size, c, s, tol=0.0) for c, s in avoid):
        return False
    # nor anything over it: a cube set aside 2 mm under a plate's overhang was hidden
    # from above, and the robot watch saw its place as a NO-OP (helper round 11, 32)
    above = (spot[0], spot[1], (spot[2] + size[2] / 2 + SKY_MM) / 2)
    column = (size[0], size[1], SKY_MM - spot[2] - size[2] / 2)
    if any(overlap(spot, size, b.position, b.size, tol=-rules.jaw_clearance)
           or overlap(above, column, b.position, b.size, tol=0.0)
           for n, b in model.bodies.items() if n not in ignore):
        return False
    return jaws.blocker(name, spot, axis, off, rules, model) is None
