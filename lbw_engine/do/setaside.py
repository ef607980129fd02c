"""Set-asides as commands (the spots are clearing.py's): riders of a block the plan picks,
a block taken again the other way, what lies on a spot the plan is about to fill, and a
block that keeps the jaws off one the plan picks.

Each returns (why, the commands, which block, where it went), which tracing.py puts in
front of the operation's own commands (``TracedOp.aside``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from lbw_engine.do import clearing, grasp, jaws
from lbw_engine.do.expander import Command, Context, Expander
from lbw_engine.do.placement import mm, occupants
from lbw_engine.do.plan import Plan, placed
from lbw_engine.errors import TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Vec, footprints_meet, top
from lbw_engine.rules.commands import CommandRules

Aside = tuple[str, list[Command], str, Vec]
FINGER_ROOM_MM = 20.0  # beside a finger's width, what a block set aside leaves a grip


def riders(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
           focus: str, where: str, operator: str | None = None) -> list[Aside]:
    """Put each block that rests on ``focus`` unplanned on the table first (clearing.py);
    ``operator``: the one picking it."""
    out = []
    for name in clearing.unplanned_riders(plan, focus, rules, model, operator):
        sa = clearing.plan_set_aside(plan, name, rules, model)
        if sa is None:
            raise TaskFailed(f"'{name}' rests on '{focus}', which the plan picks up, and "
                             "there is no free spot on the table to set it aside")
        out.append(_aside(sa, rules, model, expander, where, lambda at, n=name: (
            f"'{n}' rests on '{focus}' where the plan does not put it: set aside at {at}")))
    return out


def regrasp(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
             focus: str, exc: grasp.NoCommonGrip, where: str
             ) -> Aside:
    """Put ``focus`` down where it can be taken the way its place needs (clearing.py)."""
    sa = clearing.plan_regrasp(plan, focus, exc.picks, exc.places, rules, model)
    if sa is None:
        raise TaskFailed(f"{exc} (and no free spot on the table to take it again the other way)")
    return _aside(sa, rules, model, expander, where, lambda at: (
        f"no one way of closing the jaws serves both where '{focus}' is and where it goes: "
        f"put down at {at} to be taken again"))


def free_grasp(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
               focus: str, exc: grasp.Blocked, where: str) -> list[Aside]:
    """Set aside one block that keeps the jaws off ``focus`` (with what rests on it, top
    first), so that a grip fits: two posts 5 mm apart along x and a lintel 12 mm south of
    one, lying free (helper round 13, 50). Only a block the plan has not placed, and one
    a grip can take to a free spot; [] if none."""
    body = model.bodies[focus]  # the fingers' room around it, which the spot must leave
    room = (body.position, tuple(v + 2 * (rules.finger[0] + FINGER_ROOM_MM) if k < 2 else v
                                 for k, v in enumerate(body.size)))
    for name in dict.fromkeys(exc.hits.values()):
        stack = [name, *model.supported_by(name)]
        if name == focus or any(n in model.placed or model.holding() == n for n in stack):
            continue
        # its own jaws must be clear: a post hemmed in as well would be knocked
        out, _ = _stack_aside(plan, rules, model, expander, stack, where, lambda at, n: (
            f"'{n}' keeps the jaws off '{focus}': set aside at {at}"), [room], clear_jaws=True)
        if out:
            return out
    return []


def grip_freed(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
               focus: str, goal: Vec, ahead: grasp.PlaceAhead, exc: grasp.Blocked,
               where: str, aside: list[Aside]) -> tuple[int, float]:
    """A grip of ``focus`` after setting aside blocks in the jaws' way (``free_grasp``),
    one at a time, appended to ``aside``: a cube with blocks 6 mm off all four sides
    needs both of one axis moved (helper round 13, v50d). The last Blocked if no block
    is left that can be moved."""
    for _ in model.bodies:
        freed = free_grasp(plan, rules, model, expander, focus, exc, where)
        if not freed:
            break
        aside += freed
        try:
            return grasp.choose(focus, goal, rules, model, ahead)
        except grasp.Blocked as again:
            exc = again
    raise exc


def _aside(sa: clearing.SetAside, rules: CommandRules, model: EnvModel, expander: Expander,
           where: str, why: Callable[[str], str]) -> Aside:
    """Put a block on its spot (``put_down``) and say so: ``why`` of the spot, the
    commands that did it, the block and the spot."""
    start = len(expander.emitted)
    spot = put_down(sa, rules, model, expander, where)
    return why(mm(spot)), expander.emitted[start:], sa.name, spot


def put_down(sa: clearing.SetAside, rules: CommandRules, model: EnvModel,
              expander: Expander, where: str) -> Vec:
    """Pick a block up and put it on its table spot (commands.yaml set-aside)."""
    size = model.bodies[sa.name].size
    spot = (sa.spot[0], sa.spot[1], sa.spot[2] + rules.release_clearance)
    ctx = Context(jaws.tool_point(sa.start, size, sa.axis, sa.offset, rules),
                  size[sa.axis] + rules.margin, where, 90.0 * sa.axis,
                  {"set-down": jaws.tool_point(spot, size, sa.axis, sa.offset, rules)})
    model.grips[sa.name] = (sa.axis, sa.offset)
    expander.run(rules.set_aside, ctx)
    model.apply((), [clearing.support_on_table(sa.name, rules)])
    return spot


def clear_goal(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
               focus: str, goal: Vec | None, where: str) -> list[Aside]:
    """Before ``focus`` is picked, set aside what lies on the spot its next place fills:
    objects the plan does not use, and plan objects not yet put where the plan wants
    them (a user's plate lying where its legs go, helper round 5's t15; a disk on the
    goal spot, t29), with whatever rests on them, top first, each on a free spot. What
    the plan has placed, or no grip can take, stays, and the place reports it."""
    out: list[Aside] = []
    if goal is None:
        return out
    for name in occupants(goal, focus, model) + trapped(plan, rules, goal, focus, model):
        stack = [name, *model.supported_by(name)]
        if any(n in model.placed or model.holding() == n for n in stack):
            continue
        done, whole = _stack_aside(plan, rules, model, expander, stack, where, lambda at, n: (
            f"'{n}' lies where the plan puts '{focus}': set aside at {at}"))
        out += done
        if not whole:
            return out
    return out


def _stack_aside(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
                 stack: list[str], where: str, why: Callable[[str, str], str],
                 keep_clear: Sequence[tuple[Vec, Vec]] = (), clear_jaws: bool = False
                 ) -> tuple[list[Aside], bool]:
    """Set a stack's blocks aside, top first, each on a free spot (clearing.py, away from
    ``keep_clear``; ``why(spot, block)`` says why), until one cannot be: no grip takes it,
    or (``clear_jaws``) none leaves its own jaws clear, or no spot is free. The set-asides
    made, and whether the whole stack was."""
    out: list[Aside] = []
    for n in clearing.top_first(stack, model):
        try:
            if clear_jaws:
                grasp.choose(n, model.bodies[n].position, rules, model)
            sa = clearing.plan_set_aside(plan, n, rules, model, keep_clear)
        except TaskFailed:  # no grip takes it (wider than the jaws open, hemmed in)
            sa = None
        if sa is None:
            return out, False
        out.append(_aside(sa, rules, model, expander, where, lambda at, n=n: why(at, n)))
    return out, True


SUPPORT_TOP_MM = 5.0  # a block whose top is this near a place's bottom holds it up


def trapped(plan: Plan, rules: CommandRules, goal: Vec, focus: str, model: EnvModel
            ) -> list[str]:
    """Blocks lying under where ``focus`` goes, below its supports' tops: once it is put
    there no grip reaches them (a beam lying between the two legs a crossing beam goes
    on, bench 1271: the robot took the upper beam for it). Only those the plan moves
    later, or does not use; a block the plan leaves standing under its structure stays."""
    size = model.bodies[focus].size
    bottom = goal[2] - size[2] / 2.0 - rules.release_clearance
    placed_later = placed(plan, rules.support_relations)
    riding = set(model.supported_by(focus))
    out = []
    for name, b in model.bodies.items():
        if name == focus or name in model.placed or name in riding:
            continue
        if not footprints_meet(goal, size, b.position, b.size, tol=1.5):
            continue
        if top(b.position, b.size) < bottom - SUPPORT_TOP_MM and (
                not b.relevant or name in placed_later) and not any(
                top(model.bodies[a].position, model.bodies[a].size) >= bottom - SUPPORT_TOP_MM
                for a in model.supported_by(name) if a in model.bodies):
            out.append(name)
    return out
