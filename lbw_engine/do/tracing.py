"""Plan tracing (Sec. VII-A, "trace the temporal evolution of the plan").

The plan is walked depth first in plot order; a ``$parallel`` runs its
branches in listed order unless a branch would leave a stack off balance
while another would not (balance.py). Each recognized operation (a plot leaf) gets a goal and is
expanded into commands by the Table IX rules:

* ``object`` goals — the operator's focus object where the model currently
  has it (REACH / PICK retargeted to the current ENV-node, Sec. VII-A 2a);
* ``placement`` goals — the taught support relation in the operator's SC⁺,
  kept relative to its support (``:at ... :wrt``). The paper keeps PLACE goals
  in world coordinates; a relative goal goes one step further: a sub-assembly
  built on an object that starts elsewhere still lands on it, while a support
  of ``table`` still means world coordinates. The vertical goal comes from the
  sizes (top of the supports plus half the object), as the paper corrects it;
  a horizontal goal where the object and its riders could not stand on their
  supports is moved until they can (balance.py ``steadied``).

The model is updated by every emitted primitive and, when an operator's own
leaves are done, by its SC⁻ / SC⁺ (Sec. VII-A 2c).
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.do import jaws
from lbw_engine.do.balance import steadied, unbalanced
from lbw_engine.do.expander import Command, Context, Expander, fvec
from lbw_engine.do.plan import Operator, Plan, Relation
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import TABLE, Vec, overlap, top
from lbw_engine.rules.commands import CommandRules

NOT_OBJECTS = frozenset({TABLE, "hand"})


@dataclass
class TracedOp:
    """One recognized operation as executed: its goal and its commands."""

    operator: str  # the plan operator whose plot holds this leaf
    operator_class: str
    leaf: str
    operation: str
    focus: str | None
    goal: Vec | None
    arm_goal: Vec | None = None
    commands: list[Command] = field(default_factory=list)
    steadied: float = 0.0  # mm the placement was moved so its load stands (balance.py)


@dataclass
class Trace:
    """The traced plan: operations in execution order, and the model at the end."""

    ops: list[TracedOp]
    model: EnvModel

    @property
    def commands(self) -> list[Command]:
        """All manipulator commands in order."""
        return [c for op in self.ops for c in op.commands]


def trace(plan: Plan, rules: CommandRules, model: EnvModel,
          on_operator: Callable[[str, EnvModel], None] | None = None,
          roots: Sequence[str] | None = None) -> Trace:
    """Walk the plan depth first, expanding each leaf against the (updated) model.

    ``on_operator(name, model)`` is called as each operator is done (the
    monitor's expected state after it); ``roots`` traces just those operators,
    in that order (a local repair), instead of the plan's root.
    """
    ops: list[TracedOp] = []
    walker = _Walker(plan, rules, model, ops)
    walker.on_operator = on_operator
    for name in roots if roots is not None else [plan.root]:
        walker.operator(name)
    return Trace(ops, model)


class _Walker:
    """Depth-first plan walk; a ``$parallel`` runs its branches in a balanced order."""

    def __init__(self, plan: Plan, rules: CommandRules, model: EnvModel,
                 ops: list[TracedOp]) -> None:
        """Walk ``plan`` against ``model``, appending traced leaves to ``ops``."""
        self.plan, self.rules, self.model, self.ops = plan, rules, model, ops
        self.expander = Expander(rules, model)
        self.on_operator: Callable[[str, EnvModel], None] | None = None

    def operator(self, name: str) -> None:
        """Trace one operator's plot, then apply its SC⁻ / SC⁺ if it has leaves."""
        op = self.plan.operators[name]
        if self.plot(op, op.plot):
            self.model.apply(op.sc_minus, op.sc_plus)
        if self.on_operator is not None:
            self.on_operator(name, self.model)

    def plot(self, op: Operator, plot: Any) -> bool:
        """Trace a plot of ``op``; True if it held a leaf of ``op`` itself."""
        if plot[0] == "$action":
            if plot[1] in self.plan.operators:
                self.operator(plot[1])
                return False
            self.ops.append(_leaf(self.plan, self.rules, self.model, self.expander, op,
                                  plot[1]))
            return True
        branches = list(plot[1:])
        has_leaves = False
        while branches:
            first = self._balanced(op, branches) if plot[0] == "$parallel" else 0
            has_leaves |= self.plot(op, branches.pop(first))
        return has_leaves

    def _balanced(self, op: Operator, branches: list[Any]) -> int:
        """The first listed branch after which every stack still stands (balance.py).

        A ``$parallel`` orders nothing (Fig. 17), so a branch that would tip
        the structure over waits for the others; if every branch would, the
        listed order is kept. Each candidate is traced on a copy of the model.
        """
        if len(branches) < 2:
            return 0
        for i, branch in enumerate(branches):
            trial = _Walker(self.plan, self.rules, copy.deepcopy(self.model), [])
            try:
                trial.plot(op, branch)
            except TaskFailed:
                continue
            if unbalanced(trial.model, self.rules.balance_margin) is None:
                return i
        return 0


def trace_leaf(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
               op: Operator, leaf: str) -> TracedOp:
    """One leaf's goal and commands against the model as it is now (a behaviour tree's leaf)."""
    return _leaf(plan, rules, model, expander, op, leaf)


def _leaf(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
          op: Operator, leaf: str) -> TracedOp:
    """Find one leaf's goal and expand its steps."""
    operation = rules.operation_of(plan.leaf_operations[leaf])
    where = f"operators.{op.name}.plot: {leaf}"
    rule = rules.operations.get(operation)
    if rule is None:
        raise InputError(f"operation {operation} has no expansion in {rules.file} "
                         f"(known: {', '.join(sorted(rules.operations))})",
                         file=plan.file, where=where)
    focus = focus_object(op, rules, model)
    goal, moved = None, 0.0
    for source in rule.goal:
        goal, moved = _goal(source, op, focus, rules, model, plan.file, where)
        if goal is not None:
            break
    if goal is None and rule.goal:
        # The rules name where the goal comes from, but this plan offers none of it
        # (e.g. a touch made while holding an object): the task cannot be done.
        raise TaskFailed(f"{leaf} in {op.name} ({op.cls}): none of its goal sources "
                         f"({', '.join(rule.goal)}) gives a position in this plan")
    width = rules.margin
    grip = goal
    if focus is not None:
        size = model.bodies[focus].size
        width += size[rules.jaw_axis]
        if goal is not None:
            grip = _grip_point(focus, goal, rule.check_jaws, rules, model)
    cmds = expander.run(rule.steps, Context(grip, width, where))
    arm_goal = rules.arm_frame.to_arm(grip) if grip is not None else None
    return TracedOp(op.name, op.cls, leaf, operation, focus, goal, arm_goal, cmds, moved)


def _grip_point(focus: str, goal: Vec, check: bool, rules: CommandRules,
                model: EnvModel) -> Vec:
    """Where the arm's tool point goes for an object goal: the grip centre (jaws.py).

    Before a grasp the grip offset is chosen; while the object is held it is kept.
    """
    if model.holding() == focus:
        dy = model.grip_offsets.get(focus, 0.0)
        hit = jaws.blocker(focus, goal, dy, rules, model)
    else:
        dy, hit = jaws.choose_offset(focus, goal, rules, model)
        model.grip_offsets[focus] = dy
    if hit is not None and check:
        raise TaskFailed(f"the gripper cannot hold '{focus}' at {_mm(goal)}: a jaw would hit "
                         f"'{hit}' at {_mm(model.bodies[hit].position)}")
    shift = [0.0, 0.0]
    shift[1 - rules.jaw_axis] = dy
    return (goal[0] + shift[0], goal[1] + shift[1], goal[2] + rules.grip_offset(
        model.bodies[focus].size))


def focus_object(op: Operator, rules: CommandRules, model: EnvModel) -> str | None:
    """The object an operator moves or touches (commands.yaml ``focus``)."""
    for rels in (op.sc_plus, op.sc_minus):
        for r in rels:
            if r.type in rules.focus_relations and r.subject in model.bodies:
                return r.subject
    for slot in rules.focus_slots:
        for name in op.slots[slot]:
            if name not in NOT_OBJECTS and name in model.bodies:
                return name
    return None


def _goal(source: str, op: Operator, focus: str | None, rules: CommandRules,
          model: EnvModel, file: str, where: str) -> tuple[Vec | None, float]:
    """A goal from one source (commands.yaml ``goal``), or None if it does not apply,
    and how far a placement was moved so that its load stands."""
    if focus is None:
        return None, 0.0
    if source == "object":
        return model.bodies[focus].position, 0.0
    rel = next((r for r in op.sc_plus
                if r.subject == focus and r.type in rules.support_relations), None)
    if rel is None:
        return None, 0.0
    return _placement(rel, focus, rules, model, file, where)


def placement_goal(rel: Relation, focus: str, rules: CommandRules, model: EnvModel,
                   file: str = "<plan>", where: str = "") -> Vec:
    """Where ``focus`` goes for a taught support relation, in the current model."""
    return _placement(rel, focus, rules, model, file, where)[0]


def _placement(rel: Relation, focus: str, rules: CommandRules, model: EnvModel,
               file: str, where: str) -> tuple[Vec, float]:
    """placement_goal, and how far the taught spot was moved so the load stands."""
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
                f"cannot place '{focus}' at {_mm(goal)}: the spot is occupied by "
                f"'{name}'{kind} at {_mm(b.position)}"
            )


def _mm(v: Vec) -> str:
    """A position for messages."""
    return "(" + ", ".join(f"{c:.0f}" for c in v) + ") mm"


def format_commands(tr: Trace, title: str = "") -> str:
    """commands.txt in the manner of Fig. 24: operator, goal, operation, commands."""
    n = len(tr.commands)
    lines = [f";;; {title} — {n} manipulator commands (positions in arm coordinates, mm)"
             if title else f";;; {n} manipulator commands (positions in arm coordinates, mm)"]
    last_op = last_goal = None
    for op in tr.ops:
        if not op.commands:
            continue
        if op.operator != last_op:
            lines.append(f"<<{op.operator_class.capitalize()}>> {op.operator}")
            last_op, last_goal = op.operator, None
        if op.goal is not None and op.goal != last_goal:
            lines.append(f" GOAL-POSITION {fvec(op.goal)}")
            lines.append(f" ARM GOAL POSITION {fvec(op.arm_goal)}")
            if op.steadied:
                lines.append(f" ; moved {op.steadied:.1f} mm from the taught spot so that "
                             f"'{op.focus}' and its load stand on the supports")
            last_goal = op.goal
        lines.append(f" <{op.operation.lower()}>")
        lines.extend(f" {c.text()}" for c in op.commands)
    return "\n".join(lines) + "\n"
