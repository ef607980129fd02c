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

from lbw_engine.do import fine, grasp, jaws, setaside
from lbw_engine.do.balance import unbalanced
from lbw_engine.do.expander import Command, Context, Expander
from lbw_engine.do.fine import Alignment, PlacePlan
from lbw_engine.do.ordering import feasible_order
from lbw_engine.do.placement import NOT_OBJECTS, mm, placement, taught_positions, to_come
from lbw_engine.do.plan import Operator, Plan, action_names, placed
from lbw_engine.errors import InputError, TaskFailed
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Vec
from lbw_engine.rules.commands import CommandRules, OperationRule


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
    wrist: float | None = None  # the jaw direction of the grip (degrees from world x)
    fine: str | None = None  # the place's fine motion: "slide" | "push" (fine.py)
    alignment: Alignment | None = None  # faces the place makes coplanar (verification)
    skipped: str | None = None  # a harmless leaf left out, and why
    # blocks put down first (clearing.py): why, how many commands, which block, where (x, y)
    aside: list[tuple[str, int, str, tuple[float, float]]] = field(default_factory=list)
    carries: tuple[str, ...] = ()  # blocks riding on the focus when it was traced


@dataclass
class Trace:
    """The traced plan: operations in execution order, and the model at the end."""

    ops: list[TracedOp]
    model: EnvModel

    @property
    def commands(self) -> list[Command]:
        """All manipulator commands in order."""
        return [c for op in self.ops for c in op.commands]

    @property
    def alignments(self) -> list[Alignment]:
        """The coplanar faces the places make (the demonstration's ALIGNs), last per object."""
        return alignments_of(self.ops)


def alignments_of(ops: Sequence[TracedOp]) -> list[Alignment]:
    """The coplanar faces some traced operations make, the last per placed object."""
    last = {op.alignment.subject: op.alignment for op in ops if op.alignment}
    return list(last.values())


def trace(plan: Plan, rules: CommandRules, model: EnvModel,
          on_operator: Callable[[str, EnvModel], None] | None = None,
          roots: Sequence[str] | None = None) -> Trace:
    """Walk the plan depth first, expanding each leaf against the (updated) model.

    ``on_operator(name, model)`` is called as each operator is done (the
    monitor's expected state after it); ``roots`` traces just those operators,
    in that order (a local repair), instead of the plan's root.
    """
    why = jaws.unmovable(sorted(placed(plan, rules.support_relations)), rules, model)
    if why is not None:  # said first: a block the jaws cannot take is the root cause
        raise TaskFailed(why)
    ops: list[TracedOp] = []
    walker = _Walker(plan, rules, model, ops)
    walker.on_operator = on_operator
    for name in roots if roots is not None else [plan.root]:
        walker.operator(name)
    return Trace(ops, model)


class _Walker:
    """Depth-first plan walk; a ``$parallel`` runs its branches in an order in which all can
    be done and every stack stands (else in a balanced order, branch by branch)."""

    def __init__(self, plan: Plan, rules: CommandRules, model: EnvModel,
                 ops: list[TracedOp], search: bool = True) -> None:
        """Walk ``plan`` against ``model``, appending traced leaves to ``ops``; ``search``:
        look for a whole order of a ``$parallel`` (a trial walk does not: its searches
        would nest, one budget inside another)."""
        self.plan, self.rules, self.model, self.ops = plan, rules, model, ops
        self.search = search
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
            # a trial walk (search off) frees no grip: an order that needs no set-aside wins
            self.ops.append(_leaf(self.plan, self.rules, self.model, self.expander, op,
                                  plot[1], free=self.search))
            return True
        branches = list(plot[1:])
        has_leaves = False
        order = self._order(op, branches) if plot[0] == "$parallel" and self.search else None
        if order is not None:
            for i in order:
                has_leaves |= self.plot(op, branches[i])
            return has_leaves
        while branches:
            first = self._balanced(op, branches) if plot[0] == "$parallel" else 0
            has_leaves |= self.plot(op, branches.pop(first))
        return has_leaves

    def _order(self, op: Operator, branches: list[Any]) -> list[int] | None:
        """An order of a ``$parallel``'s branches in which each can be done and leaves every
        stack standing (ordering.py), each branch traced on a copy of the model."""
        if len(branches) < 2:
            return None

        def attempt(model: EnvModel, i: int) -> EnvModel | None:
            trial = _Walker(self.plan, self.rules, copy.deepcopy(model), [], search=False)
            try:
                trial.plot(op, branches[i])
            except TaskFailed:
                return None
            ok = unbalanced(trial.model, self.rules.balance_margin) is None
            return trial.model if ok else None

        return feasible_order(self.model, len(branches), attempt)

    def _balanced(self, op: Operator, branches: list[Any]) -> int:
        """The first listed branch after which every stack still stands (balance.py).

        A ``$parallel`` orders nothing (Fig. 17), so a branch that would tip
        the structure over waits for the others; if every branch would, the
        listed order is kept. Each candidate is traced on a copy of the model.
        """
        if len(branches) < 2:
            return 0
        for i, branch in enumerate(branches):
            trial = _Walker(self.plan, self.rules, copy.deepcopy(self.model), [], search=False)
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
          op: Operator, leaf: str, free: bool = True) -> TracedOp:
    """Find one leaf's goal and grip and expand its steps (``free``: a block that keeps the
    jaws off the object may be set aside first).

    A leaf of a harmless operator (commands.yaml ``harmless``: a FAKE changes
    nothing) that cannot be done is left out rather than stopping the task.
    """
    operation = rules.operation_of(plan.leaf_operations[leaf])
    where = f"operators.{op.name}.plot: {leaf}"
    rule = rules.operations.get(operation)
    if rule is None:
        raise InputError(f"operation {operation} has no expansion in {rules.file} "
                         f"(known: {', '.join(sorted(rules.operations))})",
                         file=plan.file, where=where)
    try:
        return _expand(plan, rules, model, expander, op, leaf, operation, rule, where, free)
    except TaskFailed as exc:
        if op.cls not in rules.harmless:
            raise
        return TracedOp(op.name, op.cls, leaf, operation, None, None, skipped=str(exc))


def _expand(plan: Plan, rules: CommandRules, model: EnvModel, expander: Expander,
            op: Operator, leaf: str, operation: str, rule: OperationRule,
            where: str, free: bool = True) -> TracedOp:
    """The goal, the grip (jaws.py, grasp.py) and the place's fine motion (fine.py)."""
    focus = focus_object(op, rules, model)
    goal, moved = _first_goal(rule, op, focus, rules, model, plan, where)
    if goal is None and rule.goal:
        # The rules name where the goal comes from, but this plan offers none of it
        # (e.g. a put whose placement was lost): the task cannot be done.
        raise TaskFailed(f"{leaf} in {op.name} ({op.cls}): none of its goal sources "
                         f"({', '.join(rule.goal)}) gives a position in this plan")
    ctx = Context(goal, rules.margin, where, model.wrist)
    steps, place, aside = rule.steps, None, []
    if focus is not None and goal is not None:
        size = model.bodies[focus].size
        if model.holding() != focus and rule.check_jaws:
            aside = setaside.riders(plan, rules, model, expander, focus, where, op.name)
            aside += setaside.clear_goal(plan, rules, model, expander, focus,
                                         _next_goal(plan, rules, model, op, leaf, focus), where)
            if any(name == focus for _, _, name, _ in aside):  # it was moved itself
                goal, moved = _first_goal(rule, op, focus, rules, model, plan, where)
                ctx.goal = goal
        if model.holding() == focus:
            axis, off = model.grips.get(focus, (rules.jaw_axes[0], 0.0))
            if rule.check_jaws:
                place = _place_plan(op, focus, goal, axis, off, rules, model)
                goal, steps = place.goal, _fine_steps(rule, place, plan.file, where)
        else:
            ahead = _ahead(plan, rules, model, op, leaf, focus)
            try:
                axis, off = grasp.choose(focus, goal, rules, model, ahead, rule.check_jaws)
            except grasp.NoCommonGrip as exc:  # put it down on the way, take it the other way
                aside.append(setaside.regrasp(plan, rules, model, expander, focus, exc, where))
                goal = model.bodies[focus].position
                axis, off = grasp.choose(focus, goal, rules, model, ahead, rule.check_jaws)
            except grasp.Blocked as exc:  # free blocks hem it in: set them aside first
                if not free:
                    raise
                axis, off = setaside.grip_freed(plan, rules, model, expander, focus, goal,
                                                ahead, exc, where, aside)
            model.grips[focus] = (axis, off)
        ctx.goal = jaws.tool_point(goal, size, axis, off, rules)
        ctx.width, ctx.wrist = size[axis] + rules.margin, 90.0 * axis
        if place is not None and place.set_down is not None:
            ctx.fine["set-down"] = jaws.tool_point(place.set_down, size, axis, off, rules)
            if place.push_from is not None:
                ctx.fine.update({"push-from": place.push_from, "push-to": place.push_to})
                ctx.pushed = (focus, goal)
    cmds = [c for _, done, _, _ in aside for c in done] + expander.run(steps, ctx)
    arm_goal = rules.arm_frame.to_arm(ctx.goal) if ctx.goal is not None else None
    return TracedOp(op.name, op.cls, leaf, operation, focus, goal, arm_goal, cmds, moved,
                    wrist=ctx.wrist if focus is not None else None,
                    fine=place.kind if place is not None and place.set_down else None,
                    alignment=place.alignment if place is not None else None,
                    aside=[(note, len(done), name, (spot[0], spot[1]))
                           for note, done, name, spot in aside],
                    carries=tuple(model.supported_by(focus)) if focus is not None else ())


def _place_plan(op: Operator, focus: str, goal: Vec, axis: int, off: float,
                rules: CommandRules, model: EnvModel) -> PlacePlan:
    """How the held ``focus`` is put at ``goal`` (fine.py), or TaskFailed naming why not."""
    found = fine.aligned(op, focus, goal, rules, model)
    plan, why = fine.plan_place(focus, goal, axis, off, rules, model,
                                found[1] if found else None)
    if plan is None:
        raise TaskFailed(f"cannot put '{focus}' down at {mm(goal)} with the jaws along "
                         f"{jaws.AXIS_NAMES[axis]}: {why}")
    return plan


def _fine_steps(rule: OperationRule, place: PlacePlan, file: str, where: str) -> tuple:
    """The steps of the rule for the place's kind (commands.yaml ``slide`` / ``push``)."""
    if place.set_down is None:
        return rule.steps
    if place.kind not in rule.fine:
        raise InputError(f"the place needs a fine motion ({place.kind}), for which operation "
                         f"{rule.name} gives no steps", file=file, where=where)
    return rule.fine[place.kind]


def _ahead(plan: Plan, rules: CommandRules, model: EnvModel, op: Operator, leaf: str,
           focus: str) -> grasp.PlaceAhead:
    """How the next place of ``focus`` after ``leaf`` would be made, per grip (grasp.py).

    Between a pick and its place nothing else moves (the hand holds one object),
    so the place is planned against the model as it is now.
    """
    nxt = _next_place(plan, rules, op.name, leaf, focus)

    def place(axis: int, off: float) -> tuple[PlacePlan | None, str] | None:
        if nxt is None:
            return None
        try:
            goal = _goal("placement", nxt, focus, rules, model, plan, "")[0]
            return _place_plan(nxt, focus, goal, axis, off, rules, model), ""
        except TaskFailed as exc:
            return None, str(exc)
    return place


def _next_goal(plan: Plan, rules: CommandRules, model: EnvModel, op: Operator, leaf: str,
               focus: str) -> Vec | None:
    """Where the next place of ``focus`` after ``leaf`` puts it, taken or not (None if
    there is none, or it cannot be worked out now)."""
    nxt = _next_place(plan, rules, op.name, leaf, focus)
    try:
        return None if nxt is None else \
            _goal("placement", nxt, focus, rules, model, plan, "", check=False)[0]
    except TaskFailed:
        return None


def _next_place(plan: Plan, rules: CommandRules, op_name: str, leaf: str,
                focus: str) -> Operator | None:
    """The first operator after ``leaf`` (plot order) with a place leaf that puts ``focus``."""
    order = _leaves(plan, plan.root)
    later = order[order.index((op_name, leaf)) + 1:] if (op_name, leaf) in order else []
    for name, other in later:
        rule = rules.operations.get(rules.operation_of(plan.leaf_operations[other]))
        op = plan.operators[name]
        if rule is not None and rule.check_jaws and "placement" in rule.goal and any(
                r.subject == focus and r.type in rules.support_relations for r in op.sc_plus):
            return op
    return None


def _leaves(plan: Plan, name: str) -> list[tuple[str, str]]:
    """(operator, leaf) pairs in depth-first plot order."""
    out: list[tuple[str, str]] = []
    for item in action_names(plan.operators[name].plot):
        out += _leaves(plan, item) if item in plan.operators else [(name, item)]
    return out


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


def _first_goal(rule: OperationRule, op: Operator, focus: str | None, rules: CommandRules,
                model: EnvModel, plan: Plan, where: str) -> tuple[Vec | None, float]:
    """The goal from the first of the rule's sources that gives one (commands.yaml)."""
    for source in rule.goal:
        goal, moved = _goal(source, op, focus, rules, model, plan, where)
        if goal is not None:
            return goal, moved
    return None, 0.0


def _goal(source: str, op: Operator, focus: str | None, rules: CommandRules,
          model: EnvModel, plan: Plan, where: str, check: bool = True
          ) -> tuple[Vec | None, float]:
    """A goal from one source (commands.yaml ``goal``), or None if it does not apply,
    and how far a placement was moved so that its load stands (``check``: a spot taken
    is a TaskFailed)."""
    if focus is None:
        return None, 0.0
    if source == "object":
        return model.bodies[focus].position, 0.0
    rel = next((r for r in op.sc_plus
                if r.subject == focus and r.type in rules.support_relations), None)
    if rel is None:
        return None, 0.0
    goal, moved = placement(rel, focus, rules, model, plan.file, where,
                            taught_positions(op.si, rules.support_relations, op.sc_plus), check,
                            to_come(plan, focus, rules.support_relations, model))
    found = fine.aligned(op, focus, goal, rules, model)
    if found is not None:  # the demonstrated ALIGN: flush with its partner (fine.py)
        goal = found[0]
    return goal, moved
