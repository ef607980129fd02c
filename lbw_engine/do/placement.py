"""Placement goals (Sec. VII-A 2b): where a taught support relation puts an object now.

The taught ``:at`` is kept relative to its support (``:wrt X``, X not the
table) or in world coordinates; no ``:at`` means the centre of the supports.
The vertical goal comes from the sizes, as the paper corrects it; a spot where
the load would tip is moved until it stands (balance.py ``steadied``); a spot
taken by another object makes the task impossible.
"""

from __future__ import annotations

from lbw_engine.do.balance import steadied
from lbw_engine.do.plan import Relation
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import TABLE, Vec, overlap, top
from lbw_engine.rules.commands import CommandRules

NOT_OBJECTS = frozenset({TABLE, "hand"})


def placement(rel: Relation, focus: str, rules: CommandRules, model: EnvModel,
              file: str = "<plan>", where: str = "") -> tuple[Vec, float]:
    """Where ``focus`` goes for a taught support relation in the current model, and how
    far the taught spot was moved so that the load stands."""
    for s in [*rel.objects, *([rel.wrt] if rel.wrt else [])]:
        if s not in NOT_OBJECTS and s not in model.bodies:
            raise InputError(f"the relation names '{s}', which is not a plan object",
                             file=file, where=where)
    supports = [s for s in rel.objects if s != TABLE]
    if rel.at is not None and rel.wrt not in (None, TABLE):
        ref = model.bodies[rel.wrt].position  # relative to the support's current place
        xy = (ref[0] + rel.at[0], ref[1] + rel.at[1])
    elif rel.at is not None:
        xy = (rel.at[0], rel.at[1])  # world frame (on the table, or no :wrt)
    elif supports:
        ps = [model.bodies[s].position for s in supports]  # centre of the supports
        xy = (sum(p[0] for p in ps) / len(ps), sum(p[1] for p in ps) / len(ps))
    else:
        raise InputError(f"the placement of '{focus}' on the table has no :at position",
                         file=file, where=where)
    # A spot where the object and its riders would tip off their supports cannot be
    # what the demonstration showed (that structure stood): its offset was measured
    # wrong. Put the load where it stands, as near the taught spot as that allows.
    xy, moved = steadied(model, focus, xy, supports, rules.balance_margin, rules.steady_margin)
    size = model.bodies[focus].size
    rest = model.settled(supports)  # supports rest on theirs, not at their release height
    base = max((top(rest[s], model.bodies[s].size) for s in supports), default=0.0)
    goal = (xy[0], xy[1], base + size[2] / 2 + rules.release_clearance)
    _check_free(goal, focus, model)
    return goal, moved


def _check_free(goal: Vec, focus: str, model: EnvModel) -> None:
    """A goal spot taken by another object makes the task impossible (exit 1)."""
    moving = {focus, *model.supported_by(focus)}
    size = model.bodies[focus].size
    for name, b in model.bodies.items():
        if name in moving:
            continue
        if overlap(goal, size, b.position, b.size, tol=1.5):
            kind = "" if b.relevant else ", an object the plan does not use,"
            raise TaskFailed(
                f"cannot place '{focus}' at {mm(goal)}: the spot is occupied by "
                f"'{name}'{kind} at {mm(b.position)}"
            )


def mm(v: Vec) -> str:
    """A position for messages."""
    return "(" + ", ".join(f"{c:.0f}" for c in v) + ") mm"
