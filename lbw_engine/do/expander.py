"""Generic Table IX expander: macros expand to steps, primitives are emitted.

The expander knows nothing about particular operations. A step names either a
macro from rules/commands.yaml (expand its steps with the parameters bound)
or a primitive (evaluate the arguments, convert positions to arm coordinates,
emit, and update the environment model). Arguments are evaluated when their
step is reached, so ``hand-pos`` is where the previous amove left the hand.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from lbw_engine.errors import InputError
from lbw_engine.model.env import EnvModel
from lbw_engine.model.geometry import Vec
from lbw_engine.rules.commands import GLOBALS, PRIMITIVES, CommandRules, Expr, Step

NULL_MOVE_MM = 0.05  # an amove shorter than this goes nowhere (skip_null_moves)
CLEAR_MM = 10.0  # a carried block passes this far above the tallest other object


@dataclass(frozen=True)
class Command:
    """One manipulator command: amove to an arm point, or a gripper command."""

    name: str
    world: Vec | None = None  # amove, push: target in world coordinates (mm)
    arm: Vec | None = None  # amove, push: the same target in arm coordinates
    width: float | None = None  # open-hand: jaw opening (mm)
    angle: float | None = None  # turn-wrist: jaw direction, degrees from world x

    def text(self) -> str:
        """The command as Fig. 24 prints it."""
        if self.arm is not None:
            return f"{self.name} {fvec(self.arm)}"
        if self.width is not None:
            return f"{self.name} {self.width:.1f}"
        if self.angle is not None:
            return f"{self.name} {self.angle:.1f}"
        return self.name


def fvec(v: Vec) -> str:
    """A vector in the paper's EusLisp notation, #f(x y z)."""
    return "#f(" + " ".join(f"{c:.1f}" for c in v) + ")"


@dataclass
class Context:
    """What the globals of an expression refer to for the current operation."""

    goal: Vec | None
    width: float
    where: str  # for error messages: the plan operator and leaf
    wrist: float = 0.0  # the jaw direction the grip needs (degrees from world x)
    fine: dict[str, Vec] = field(default_factory=dict)  # set-down, push-from, push-to
    pushed: tuple[str, Vec] | None = None  # the object a push moves, and its goal centre


class Expander:
    """Expands steps against a model, collecting the emitted commands."""

    def __init__(self, rules: CommandRules, model: EnvModel) -> None:
        self.rules = rules
        self.model = model
        self.emitted: list[Command] = []

    def run(self, steps: tuple[Step, ...], ctx: Context,
            scope: Mapping[str, object] | None = None) -> list[Command]:
        """Expand ``steps``; return the commands emitted by them."""
        start = len(self.emitted)
        self._run(steps, ctx, dict(scope or {}))
        return self.emitted[start:]

    def _run(self, steps: tuple[Step, ...], ctx: Context, scope: dict[str, object]) -> None:
        """Expand steps depth first: macros recurse, primitives are emitted."""
        for step in steps:
            args = [self._eval(a, ctx, scope) for a in step.args]
            if step.name in PRIMITIVES:
                self._primitive(step.name, args, ctx)
            else:
                macro = self.rules.macros[step.name]
                self._run(macro.steps, ctx, dict(zip(macro.params, args, strict=True)))

    def _value(self, name: str, ctx: Context, scope: dict[str, object]) -> object:
        """A parameter or a global."""
        if name in scope:
            return scope[name]
        if name == "goal":
            if ctx.goal is None:
                raise InputError("the operation's steps use 'goal' but no goal could be "
                                 "found for it", file=self.rules.file, where=ctx.where)
            return ctx.goal
        if name == "hand-pos":
            return self.model.hand
        if name == "approach-height":
            return self.approach_height()
        if name == "open-width":
            return ctx.width
        if name == "wrist":
            return ctx.wrist
        if name in ctx.fine:
            return ctx.fine[name]
        if GLOBALS.get(name) == "position":
            raise InputError(f"the operation's steps use '{name}', which only a fine motion "
                             "gives", file=self.rules.file, where=ctx.where)
        raise InputError(f"unknown name '{name}'", file=self.rules.file, where=ctx.where)

    def approach_height(self) -> float:
        """The approach height of rules/commands.yaml, raised where what hangs below the grip
        centre (the fingertips, or the held block's foot) would not clear every other
        object by CLEAR_MM: a 118 mm pillar gripped near its top hangs 88 mm below the
        hand, and carried at 200 mm it sweeps over a standing one (issue #12, pillars)."""
        model, hz = self.model, self.model.hand[2]
        carried = set(model.held())
        for name in list(carried):
            carried.update(model.supported_by(name))
        below = self.rules.tip
        tops = [0.0]
        for node in model.objects():
            if node.position is None or node.size is None:
                continue
            bottom, top = node.position[2] - node.size[2] / 2, node.position[2] + node.size[2] / 2
            if node.name in carried:
                below = max(below, hz - bottom)
            else:
                tops.append(top)
        return max(self.rules.approach_height, max(tops) + below + CLEAR_MM)

    def _eval(self, expr: Expr, ctx: Context, scope: dict[str, object]) -> object:
        """Evaluate a name or {xy: P, z: Q}."""
        if isinstance(expr, str):
            return self._value(expr, ctx, scope)
        p = self._position(self._value(expr[0], ctx, scope), expr[0], ctx)
        q = self._value(expr[1], ctx, scope)
        z = float(q) if isinstance(q, (int, float)) else self._position(q, expr[1], ctx)[2]
        return (p[0], p[1], z)

    def _position(self, v: object, name: str, ctx: Context) -> Vec:
        """Check that a value is a position."""
        if not (isinstance(v, tuple) and len(v) == 3):
            raise InputError(f"'{name}' is not a position", file=self.rules.file, where=ctx.where)
        return v

    def _primitive(self, name: str, args: list[object], ctx: Context) -> None:
        """Emit one primitive and apply its expected effect to the model (Sec. VII-A 2c)."""
        effect = PRIMITIVES[name].effect
        if effect in ("move", "push"):
            p = self._position(args[0], name, ctx)
            if self.rules.skip_null_moves and _dist(p, self.model.hand) < NULL_MOVE_MM:
                return
            self.emitted.append(Command(name, world=p, arm=self.rules.arm_frame.to_arm(p)))
            self.model.move_hand(p)
            if effect == "push" and ctx.pushed is not None:
                obj, to = ctx.pushed  # the closed jaws bring it to its goal (fine.py)
                at = self.model.bodies[obj].position
                self.model.shove(obj, (to[0] - at[0], to[1] - at[1], to[2] - at[2]))
        elif effect == "turn":
            angle = args[0]
            if not isinstance(angle, (int, float)):
                raise InputError(f"'{name}' needs an angle", file=self.rules.file,
                                 where=ctx.where)
            if self.rules.skip_null_moves and abs(angle - self.model.wrist) < 1e-6:
                return
            self.emitted.append(Command(name, angle=float(angle)))
            self.model.wrist = float(angle)
        elif effect == "release":
            width = args[0]
            if not isinstance(width, (int, float)):
                raise InputError(f"'{name}' needs a width", file=self.rules.file, where=ctx.where)
            self.emitted.append(Command(name, width=float(width)))
            self.model.release()
        else:
            self.emitted.append(Command(name))
            self.model.grasp()


def _dist(a: Vec, b: Vec) -> float:
    """Euclidean distance."""
    return sum((a[k] - b[k]) ** 2 for k in range(3)) ** 0.5
