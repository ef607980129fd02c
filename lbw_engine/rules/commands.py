"""rules/commands.yaml: Table IX command expansion, loaded and checked at load time.

The file holds the world→arm transform, the approach height, the gripper
margin, which recognized operation expands to which steps, and the Table IX
macros. Everything is validated here — unknown keys, unknown macro or
primitive names, wrong argument counts, unknown expression names, recursion —
with errors naming the file and line, so a bad file stops before anything runs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lbw_engine.errors import InputError
from lbw_engine.guard import Place, number, shorten
from lbw_engine.yamlio import line_of, load_file


@dataclass(frozen=True)
class Primitive:
    """A manipulator command: its argument kinds and its effect on the model."""

    args: tuple[str, ...]
    effect: str  # "move" | "release" | "grasp"


# The manipulator's primitive commands (Sec. VII-B), a closed registry.
PRIMITIVES: dict[str, Primitive] = {
    "amove": Primitive(("position",), "move"),
    "open-hand": Primitive(("width",), "release"),
    "close-hand": Primitive((), "grasp"),
}
# Names every expression may use besides macro parameters, with their kind.
GLOBALS: dict[str, str] = {
    "goal": "position",
    "hand-pos": "position",
    "approach": "height",
    "open-width": "width",
}
GOAL_SOURCES = ("object", "placement")
JAW_AXES = {"x": 0, "y": 1}

_TOP = {
    "arm_frame", "approach_height", "home", "skip_null_moves", "gripper", "release_clearance",
    "support_relations", "focus", "operations", "macros", "labels", "balance_margin",
    "steady_margin",
}
_REQUIRED = _TOP - {"skip_null_moves", "release_clearance", "labels", "balance_margin",
                    "steady_margin"}

Expr = str | tuple[str, str]  # a name, or (xy-name, z-name) for {xy: P, z: Q}


@dataclass(frozen=True)
class Step:
    """One line of an expansion: a macro call or a primitive, with argument expressions."""

    name: str
    args: tuple[Expr, ...]
    line: int | None = None


@dataclass(frozen=True)
class Macro:
    """A Table IX macro or sub-command: parameters and the steps it expands to."""

    name: str
    params: tuple[str, ...]
    steps: tuple[Step, ...]
    line: int | None = None


@dataclass(frozen=True)
class OperationRule:
    """How one recognized operation finds its goal and which steps it runs."""

    name: str
    goal: tuple[str, ...]
    steps: tuple[Step, ...]
    line: int | None = None
    check_jaws: bool = False  # fail when the gripper's jaws cannot reach the goal


@dataclass(frozen=True)
class ArmFrame:
    """World → arm coordinates: arm = rotation · world + offset (Fig. 24)."""

    rotation: tuple[tuple[float, float, float], ...]
    offset: tuple[float, float, float]

    def to_arm(self, p: tuple[float, float, float]) -> tuple[float, float, float]:
        """A world point in arm coordinates."""
        v = np.asarray(self.rotation) @ np.asarray(p, float) + np.asarray(self.offset)
        return tuple(float(c) for c in v)

    def to_world(self, p: tuple[float, float, float]) -> tuple[float, float, float]:
        """An arm point in world coordinates (the rotation is orthonormal)."""
        v = np.asarray(self.rotation).T @ (np.asarray(p, float) - np.asarray(self.offset))
        return tuple(float(c) for c in v)


@dataclass(frozen=True)
class CommandRules:
    """The validated content of rules/commands.yaml."""

    arm_frame: ArmFrame
    approach_height: float
    home: tuple[float, float, float]
    skip_null_moves: bool
    jaw_axis: int
    margin: float
    tip: float
    finger: tuple[float, float, float]
    jaw_clearance: float
    tip_clearance: float
    max_below_top: float
    release_clearance: float
    support_relations: tuple[str, ...]
    focus_relations: tuple[str, ...]
    focus_slots: tuple[str, ...]
    operations: dict[str, OperationRule]
    macros: dict[str, Macro]
    file: str = "<string>"
    labels: dict[str, str] = field(default_factory=dict)  # LABEL (upper case) -> operation
    balance_margin: float = 0.0  # see balance.py
    steady_margin: float = 0.0  # see balance.steadied

    def operation_of(self, word: str) -> str:
        """The operation a plan leaf's label names (``NO`` -> ``NO-OP``)."""
        return self.labels.get(word.upper(), word.upper())

    def grip_offset(self, size: tuple[float, float, float]) -> float:
        """Height of the grip centre above an object's centre when holding it."""
        h = size[2]
        return max(h / 2 - min(h / 2, self.max_below_top), self.tip + self.tip_clearance - h / 2)


class _Ctx:
    """Where errors point: the file being read."""

    def __init__(self, file: str) -> None:
        self.file = file

    def fail(self, msg: str, container: Any, key: Any = None, where: str = "") -> InputError:
        """An InputError at container[key]."""
        return InputError(msg, file=self.file, line=line_of(container, key), where=where or None)

    def keys(self, m: Any, allowed: set[str], where: str, required: set[str] = frozenset()):
        """Check a mapping's keys: none unknown, none missing."""
        if not isinstance(m, dict):
            raise self.fail("must be a mapping", m, None, where)
        for k in m:
            if k not in allowed:
                raise self.fail(f"unknown key {shorten(k)} (allowed: {', '.join(sorted(allowed))})",
                                m, k, f"{where}.{k}".lstrip("."))
        for k in sorted(required - set(m)):
            raise self.fail(f"missing required key {shorten(k)}", m, None, where)

    def number(self, m: Any, k: Any, where: str, low: float | None = None,
               high: float | None = None, *, above: bool = False) -> float:
        """A finite real number at m[k], within [low, high] (``above``: > low) when given."""
        return number(m[k], Place(self.file, line_of(m, k), where), low, high, above=above,
                      unit="mm" if low is not None or high is not None else "")

    def vector(self, m: Any, k: Any, n: int, where: str) -> tuple[float, ...]:
        """A list of n numbers at m[k]."""
        v = m[k]
        if not isinstance(v, list) or len(v) != n:
            raise self.fail(f"must be a list of {n} numbers", m, k, where)
        return tuple(self.number(v, i, f"{where}[{i}]") for i in range(n))

    def names(self, m: Any, k: Any, where: str, allowed: tuple[str, ...] | None = None):
        """A list of strings at m[k], optionally from a closed set."""
        v = m[k]
        if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
            raise self.fail("must be a list of names", m, k, where)
        for i, s in enumerate(v):
            if allowed is not None and s not in allowed:
                raise self.fail(f"unknown name {shorten(s)} (allowed: {', '.join(allowed)})",
                                v, i, f"{where}[{i}]")
        return tuple(v)


def load(path: str | Path) -> CommandRules:
    """Load and validate a commands.yaml file."""
    return parse(load_file(path), str(path))


def load_dir(rules_dir: str | Path) -> CommandRules:
    """Load ``commands.yaml`` from a rules directory."""
    return load(Path(rules_dir) / "commands.yaml")


def parse(doc: Any, file: str = "<string>") -> CommandRules:
    """Validate a parsed commands.yaml document and build CommandRules."""
    cx = _Ctx(file)
    cx.keys(doc, _TOP, "", _REQUIRED)
    frame = _arm_frame(cx, doc["arm_frame"])
    grip_keys = {"jaw_axis", "margin", "tip", "finger", "clearance", "tip_clearance",
                 "max_below_top"}
    cx.keys(doc["gripper"], grip_keys, "gripper", grip_keys)
    jaw = doc["gripper"]["jaw_axis"]
    if jaw not in JAW_AXES:
        raise cx.fail("must be x or y", doc["gripper"], "jaw_axis", "gripper.jaw_axis")
    cx.keys(doc["focus"], {"relations", "slots"}, "focus", {"relations", "slots"})
    skip = doc.get("skip_null_moves", True)
    if not isinstance(skip, bool):
        raise cx.fail("must be true or false", doc, "skip_null_moves", "skip_null_moves")
    macros = _macros(cx, doc["macros"])
    operations = _operations(cx, doc["operations"])
    _check_calls(cx, macros, operations)
    return CommandRules(
        arm_frame=frame,
        approach_height=cx.number(doc, "approach_height", "approach_height", 0, above=True),
        home=cx.vector(doc, "home", 3, "home"),
        skip_null_moves=skip,
        jaw_axis=JAW_AXES[jaw],
        **_gripper(cx, doc["gripper"]),
        release_clearance=(cx.number(doc, "release_clearance", "release_clearance", 0)
                           if "release_clearance" in doc else 0.0),
        support_relations=cx.names(doc, "support_relations", "support_relations"),
        focus_relations=cx.names(doc["focus"], "relations", "focus.relations"),
        focus_slots=cx.names(doc["focus"], "slots", "focus.slots", ("base", "target", "special")),
        operations=operations,
        macros=macros,
        file=file,
        labels=_labels(cx, doc, operations),
        balance_margin=(cx.number(doc, "balance_margin", "balance_margin", 0)
                        if "balance_margin" in doc else 0.0),
        steady_margin=(cx.number(doc, "steady_margin", "steady_margin", 0)
                       if "steady_margin" in doc else 0.0),
    )


def _gripper(cx: _Ctx, raw: Any) -> dict[str, Any]:
    """The gripper's sizes (mm): a finger and the tip have a size > 0; margins and
    clearances are >= 0 (-0.0 is no finger: execution could not verify)."""
    def size(key: str) -> float:
        return cx.number(raw, key, f"gripper.{key}", 0, above=True)

    def gap(key: str) -> float:
        return cx.number(raw, key, f"gripper.{key}", 0)

    finger = cx.vector(raw, "finger", 3, "gripper.finger")
    for i in range(3):
        cx.number(raw["finger"], i, f"gripper.finger[{i}]", 0, above=True)
    return {"margin": gap("margin"), "tip": size("tip"), "finger": finger,
            "jaw_clearance": gap("clearance"), "tip_clearance": gap("tip_clearance"),
            "max_below_top": size("max_below_top")}


def _labels(cx: _Ctx, doc: Any, operations: dict[str, OperationRule]) -> dict[str, str]:
    """The optional labels section: leaf label -> an operation defined above."""
    raw = doc.get("labels", {})
    if not isinstance(raw, dict):
        raise cx.fail("must be a mapping of label -> operation", doc, "labels", "labels")
    out = {}
    for label, op in raw.items():
        if not isinstance(label, str) or op not in operations:
            raise cx.fail(f"{shorten(op)} is not an operation of this file", raw, label,
                          f"labels.{label}")
        out[label.upper()] = op
    return out


def _arm_frame(cx: _Ctx, raw: Any) -> ArmFrame:
    """The world→arm transform; the rotation must be orthonormal (a calibration)."""
    cx.keys(raw, {"rotation", "offset"}, "arm_frame", {"rotation", "offset"})
    rot = raw["rotation"]
    if not isinstance(rot, list) or len(rot) != 3:
        raise cx.fail("must be a 3×3 matrix (three rows)", raw, "rotation", "arm_frame.rotation")
    rows = tuple(cx.vector(rot, i, 3, f"arm_frame.rotation[{i}]") for i in range(3))
    for i, j in np.ndindex(3, 3):  # tested first: 1e300 overflows the product below
        if abs(rows[i][j]) > 1:
            raise cx.fail(f"must be orthonormal: an entry of {rows[i][j]:g} is beyond ±1",
                          rot[i], j, f"arm_frame.rotation[{i}][{j}]")
    if not np.allclose(np.asarray(rows) @ np.asarray(rows).T, np.eye(3), atol=1e-3):
        raise cx.fail("must be orthonormal (rows of unit length, at right angles)",
                      raw, "rotation", "arm_frame.rotation")
    return ArmFrame(rows, cx.vector(raw, "offset", 3, "arm_frame.offset"))


def _expr(cx: _Ctx, parent: Any, key: Any, where: str) -> Expr:
    """An argument expression: a name or {xy: NAME, z: NAME}."""
    v = parent[key]
    if isinstance(v, str):
        return v
    if isinstance(v, dict):
        cx.keys(v, {"xy", "z"}, where, {"xy", "z"})
        if not all(isinstance(v[k], str) for k in ("xy", "z")):
            raise cx.fail("xy and z must be names", parent, key, where)
        return (v["xy"], v["z"])
    raise cx.fail("must be a name or {xy: NAME, z: NAME}", parent, key, where)


def _steps(cx: _Ctx, parent: Any, key: str, where: str) -> tuple[Step, ...]:
    """A list of steps, each [NAME, ARG...]."""
    raw = parent[key]
    if not isinstance(raw, list):
        raise cx.fail("must be a list of steps [NAME, ARG...]", parent, key, where)
    out = []
    for i, item in enumerate(raw):
        w = f"{where}[{i}]"
        if not isinstance(item, list) or not item or not isinstance(item[0], str):
            raise cx.fail("a step must be a list [NAME, ARG...]", raw, i, w)
        args = tuple(_expr(cx, item, j, f"{w}[{j}]") for j in range(1, len(item)))
        out.append(Step(item[0], args, line_of(raw, i)))
    return tuple(out)


def _macros(cx: _Ctx, raw: Any) -> dict[str, Macro]:
    """The macros section."""
    if not isinstance(raw, dict):
        raise cx.fail("must be a mapping of macro name → {params, steps}", raw, None, "macros")
    out = {}
    for name, body in raw.items():
        w = f"macros.{name}"
        if name in PRIMITIVES or name in GLOBALS:
            raise cx.fail(f"{shorten(name)} is a built-in name and cannot be a macro", raw, name, w)
        cx.keys(body, {"params", "steps"}, w, {"params", "steps"})
        params = cx.names(body, "params", f"{w}.params")
        for p in params:
            if p in GLOBALS:
                raise cx.fail(f"parameter {shorten(p)} hides a global name", body, "params", w)
        out[name] = Macro(name, params, _steps(cx, body, "steps", f"{w}.steps"), line_of(raw, name))
    return out


def _operations(cx: _Ctx, raw: Any) -> dict[str, OperationRule]:
    """The operations section."""
    if not isinstance(raw, dict):
        raise cx.fail("must be a mapping of operation → {goal, steps}", raw, None, "operations")
    out = {}
    for name, body in raw.items():
        w = f"operations.{name}"
        cx.keys(body, {"goal", "steps", "check_jaws"}, w, {"goal", "steps"})
        goal = cx.names(body, "goal", f"{w}.goal", GOAL_SOURCES)
        check = body.get("check_jaws", False)
        if not isinstance(check, bool):
            raise cx.fail("must be true or false", body, "check_jaws", f"{w}.check_jaws")
        out[name] = OperationRule(name, goal, _steps(cx, body, "steps", f"{w}.steps"),
                                  line_of(raw, name), check)
    return out


def _check_calls(cx: _Ctx, macros: dict[str, Macro], ops: dict[str, OperationRule]) -> None:
    """Every step names a known macro or primitive with the right arity and known names."""
    def check(steps: tuple[Step, ...], scope: set[str], where: str) -> None:
        for s in steps:
            if s.name in PRIMITIVES:
                arity = len(PRIMITIVES[s.name].args)
            elif s.name in macros:
                arity = len(macros[s.name].params)
            else:
                raise InputError(f"unknown macro or primitive {shorten(s.name)}", file=cx.file,
                                 line=s.line, where=where)
            if len(s.args) != arity:
                raise InputError(f"{shorten(s.name)} takes {arity} argument(s), got {len(s.args)}",
                                 file=cx.file, line=s.line, where=where)
            for a in s.args:
                for n in (a,) if isinstance(a, str) else a:
                    if n not in scope and n not in GLOBALS:
                        raise InputError(f"unknown name {shorten(n)} in the arguments of "
                                         f"{shorten(s.name)}",
                                         file=cx.file, line=s.line, where=where)
    for m in macros.values():
        check(m.steps, set(m.params), f"macros.{m.name}")
    for o in ops.values():
        check(o.steps, set(), f"operations.{o.name}")
    _no_recursion(cx, macros)


def _no_recursion(cx: _Ctx, macros: dict[str, Macro]) -> None:
    """A macro may not (indirectly) expand to itself."""
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for s in macros[name].steps:
            if s.name not in macros:
                continue
            if state.get(s.name) == 1:
                cycle = " → ".join([*path, s.name])
                raise InputError(f"recursive macro expansion {cycle}", file=cx.file,
                                 line=s.line, where=f"macros.{name}")
            if s.name not in state:
                visit(s.name, [*path, s.name])
        state[name] = 2

    for name in macros:
        if name not in state:
            visit(name, [name])
