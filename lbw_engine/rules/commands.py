"""rules/commands.yaml: Table IX command expansion, loaded and checked at load time.

The file holds the world→arm transform, the height of moves, the gripper
(the ways its jaws can close, their widest opening, margins), the fine motion
(how a place into side contact is made, Sec. V-B5 / IX-C1), which recognized
operation expands to which steps, and the Table IX macros. Everything is
validated here — unknown keys, unknown macro or primitive names, wrong
argument counts, unknown expression names, recursion — with errors naming the
file and line, so a bad file stops before anything runs.
The support relations and the leaf labels are not written here: the loader
takes them from effects.yaml (roles) and operations.yaml (labels).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lbw_engine.errors import InputError
from lbw_engine.rules.analysis import PLAN_CLASSES
from lbw_engine.rules.reader import Reader
from lbw_engine.yamlio import line_of


@dataclass(frozen=True)
class Primitive:
    """A manipulator command: its argument kinds and its effect on the model."""

    args: tuple[str, ...]
    effect: str  # "move" | "release" | "grasp" | "turn" | "push"


# The manipulator's primitive commands (Sec. VII-B), a closed registry.
PRIMITIVES: dict[str, Primitive] = {
    "amove": Primitive(("position",), "move"),
    "open-hand": Primitive(("width",), "release"),
    "close-hand": Primitive((), "grasp"),
    # The wrist turns about the vertical axis: the jaws then close along the
    # direction ANGLE degrees from world x (0: along x, 90: along y), design.md "Robot".
    "turn-wrist": Primitive(("angle",), "turn"),
    # An amove whose closed jaws push the block ahead of them (the fine motion).
    "push": Primitive(("position",), "push"),
}
# Names every expression may use besides macro parameters, with their kind.
GLOBALS: dict[str, str] = {
    "goal": "position",
    "hand-pos": "position",
    "approach-height": "height",
    "open-width": "width",
    "wrist": "angle",  # the jaw direction this operation's grip needs
    "set-down": "position",  # fine motion: where the block is set down, clear of the contact
    "push-from": "position",  # fine motion: where the closed jaws come down to push it
    "push-to": "position",  # ... and where they stop, the block then at its goal
}
GOAL_SOURCES = ("object", "placement")
JAW_AXES = {"x": 0, "y": 1}
FINE_MOTIONS = ("slide", "push")  # the expansions an operation may give for a fine motion

_REQUIRED = ("arm-frame", "approach-height", "home", "gripper", "focus", "operations", "macros")
_OPTIONAL = ("skip-null-moves", "release-clearance", "balance-margin", "steady-margin",
             "fine-motion", "harmless", "set-aside")
_GRIPPER = ("jaw-axes", "max-opening", "margin", "tip", "finger", "clearance", "tip-clearance",
            "max-below-top")
_FINE = ("relations", "clearance", "contact-gap", "snap-gap", "coplanar-tolerance")

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
    check_jaws: bool = False  # fail when no grip point leaves the gripper's jaws clear
    fine: dict[str, tuple[Step, ...]] = field(default_factory=dict)  # slide / push steps


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
class ContactRules:
    """How a place into side contact is made (commands.yaml ``fine-motion``)."""

    relations: tuple[str, ...] = ()  # SC+ relations that call for the demonstrated fine motion
    clearance: float = 10.0  # mm between the set-down spot and the contact
    contact_gap: float = 0.5  # mm left between the faces in contact
    snap_gap: float = 3.0  # mm: a block nearer than this beside a goal is met by the slide
    coplanar_tolerance: float = 2.0  # mm: faces this close count as coplanar (verification)


@dataclass(frozen=True)
class CommandRules:
    """The validated content of rules/commands.yaml."""

    arm_frame: ArmFrame
    approach_height: float
    home: tuple[float, float, float]
    skip_null_moves: bool
    jaw_axes: tuple[int, ...]  # the ways the jaws may close, in order of preference
    max_opening: float
    margin: float
    tip: float
    finger: tuple[float, float, float]
    jaw_clearance: float
    tip_clearance: float
    max_below_top: float
    # fingertips above the gripped object's bottom (its height is measured by the cameras)
    bottom_clearance: float
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
    fine: ContactRules = field(default_factory=lambda: ContactRules())
    harmless: tuple[str, ...] = ()  # plan classes whose leaves never stop execution
    set_aside: tuple[Step, ...] = ()  # puts an unplanned rider on the table (do/clearing.py)

    def operation_of(self, word: str) -> str:
        """The operation a plan leaf's label names (operations.yaml labels; else its name)."""
        return self.labels.get(word.upper(), word.upper())

    def grip_offset(self, size: tuple[float, float, float]) -> float:
        """Height of the grip centre above an object's centre when holding it."""
        h = size[2]
        return max(h / 2 - min(h / 2, self.max_below_top),
                   self.tip + self.bottom_clearance - h / 2)


def parse(doc: Any, file: str, support: tuple[str, str], labels: dict[str, str],
          relations: tuple[str, ...] = ()) -> CommandRules:
    """Validate a parsed commands.yaml document and build CommandRules.

    ``support`` is the (single, multiple) support relations of effects.yaml;
    ``labels`` maps a leaf label to its operation (operations.yaml);
    ``relations`` are the relations effects.yaml defines (for ``fine-motion``).
    """
    rd = Reader(file)
    rd.keys(rd.mapping(doc, "the file"), "the file", _REQUIRED, _OPTIONAL)
    frame = _arm_frame(rd, doc["arm-frame"])
    grip = rd.mapping(doc["gripper"], "gripper", doc, "gripper")
    rd.keys(grip, "gripper", _GRIPPER, ("bottom-clearance",), where="gripper")
    jaws = rd.names(grip, "jaw-axes", "gripper.jaw-axes", JAW_AXES, "gripper.jaw-axes")
    if not jaws or len(set(jaws)) != len(jaws):
        rd.fail("must list each way the jaws close once (x, y)", grip, "jaw-axes",
                "gripper.jaw-axes")
    focus = rd.mapping(doc["focus"], "focus", doc, "focus")
    rd.keys(focus, "focus", ("relations", "slots"), where="focus")
    macros = _macros(rd, doc["macros"])
    operations = _operations(rd, doc["operations"])
    set_aside = ()
    if "set-aside" in doc:
        raw = rd.mapping(doc["set-aside"], "set-aside", doc, "set-aside")
        rd.keys(raw, "set-aside", ("steps",), where="set-aside")
        set_aside = _steps(rd, raw, "steps", "set-aside.steps")
    _check_calls(rd, macros, operations, set_aside)

    def mm(container: dict, key: str, where: str, low: float = 0.0) -> float:
        return rd.number(container, key, where, low, 1000.0, where)

    def optional(key: str) -> float:
        return mm(doc, key, key) if key in doc else 0.0

    return CommandRules(
        arm_frame=frame,
        approach_height=mm(doc, "approach-height", "approach-height"),
        home=rd.vector(doc, "home", 3, "home", -1000.0, 1000.0, "home"),
        skip_null_moves=rd.boolean(doc, "skip-null-moves", "skip-null-moves", True),
        jaw_axes=tuple(JAW_AXES[j] for j in jaws),
        max_opening=mm(grip, "max-opening", "gripper.max-opening", 1.0),
        margin=mm(grip, "margin", "gripper.margin"),
        tip=mm(grip, "tip", "gripper.tip"),
        finger=rd.vector(grip, "finger", 3, "gripper.finger", 1.0, 200.0, "gripper.finger"),
        jaw_clearance=mm(grip, "clearance", "gripper.clearance"),
        tip_clearance=(tip := mm(grip, "tip-clearance", "gripper.tip-clearance")),
        max_below_top=mm(grip, "max-below-top", "gripper.max-below-top"),
        bottom_clearance=mm(grip, "bottom-clearance", "gripper.bottom-clearance")
        if "bottom-clearance" in grip else tip,  # default: tip-clearance
        release_clearance=optional("release-clearance"),
        support_relations=tuple(support),
        focus_relations=rd.names(focus, "relations", "focus.relations", where="focus.relations"),
        focus_slots=rd.names(focus, "slots", "focus.slots", ("base", "target", "special"),
                             "focus.slots"),
        operations=operations,
        macros=macros,
        file=file,
        labels={label.upper(): op for label, op in labels.items()},
        balance_margin=optional("balance-margin"),
        steady_margin=optional("steady-margin"),
        fine=_fine(rd, doc, relations),
        harmless=rd.names(doc, "harmless", "harmless", PLAN_CLASSES, "harmless")
        if "harmless" in doc else (),
        set_aside=set_aside,
    )


def _fine(rd: Reader, doc: Any, relations: tuple[str, ...]) -> ContactRules:
    """The fine-motion section (defaults when absent)."""
    if "fine-motion" not in doc:
        return ContactRules()
    raw = rd.mapping(doc["fine-motion"], "fine-motion", doc, "fine-motion")
    rd.keys(raw, "fine-motion", _FINE, where="fine-motion")
    known = relations or None
    rels = rd.names(raw, "relations", "fine-motion.relations", known, "fine-motion.relations")
    return ContactRules(
        relations=rels,
        clearance=rd.number(raw, "clearance", "fine-motion.clearance", 1.0, 100.0,
                            "fine-motion.clearance"),
        contact_gap=rd.number(raw, "contact-gap", "fine-motion.contact-gap", 0.0, 5.0,
                              "fine-motion.contact-gap"),
        snap_gap=rd.number(raw, "snap-gap", "fine-motion.snap-gap", 0.0, 20.0,
                           "fine-motion.snap-gap"),
        coplanar_tolerance=rd.number(raw, "coplanar-tolerance", "fine-motion.coplanar-tolerance",
                                     0.0, 20.0, "fine-motion.coplanar-tolerance"),
    )


def _arm_frame(rd: Reader, raw: Any) -> ArmFrame:
    """The world→arm transform; the rotation must be orthonormal (a calibration)."""
    rd.keys(rd.mapping(raw, "arm-frame"), "arm-frame", ("rotation", "offset"), where="arm-frame")
    rot = raw["rotation"]
    if not isinstance(rot, list) or len(rot) != 3:
        rd.fail("must be a 3×3 matrix (three rows)", raw, "rotation", "arm-frame.rotation")
    rows = tuple(rd.vector(rot, i, 3, f"arm-frame.rotation[{i}]", -1.0, 1.0,
                           f"arm-frame.rotation[{i}]") for i in range(3))
    if not np.allclose(np.asarray(rows) @ np.asarray(rows).T, np.eye(3), atol=1e-3):
        rd.fail("must be orthonormal (rows of unit length, at right angles)",
                raw, "rotation", "arm-frame.rotation")
    offset = rd.vector(raw, "offset", 3, "arm-frame.offset", -1e4, 1e4, "arm-frame.offset")
    return ArmFrame(rows, offset)


def _expr(rd: Reader, parent: Any, key: Any, where: str) -> Expr:
    """An argument expression: a name or {xy: NAME, z: NAME}."""
    v = parent[key]
    if isinstance(v, str):
        return v
    if isinstance(v, dict):
        rd.keys(v, "an expression", ("xy", "z"), where=where)
        if not all(isinstance(v[k], str) for k in ("xy", "z")):
            rd.fail("xy and z must be names", parent, key, where)
        return (v["xy"], v["z"])
    rd.fail("must be a name or {xy: NAME, z: NAME}", parent, key, where)


def _steps(rd: Reader, parent: Any, key: str, where: str) -> tuple[Step, ...]:
    """A list of steps, each [NAME, ARG...]."""
    raw = parent[key]
    if not isinstance(raw, list):
        rd.fail("must be a list of steps [NAME, ARG...]", parent, key, where)
    out = []
    for i, item in enumerate(raw):
        w = f"{where}[{i}]"
        if not isinstance(item, list) or not item or not isinstance(item[0], str):
            rd.fail("a step must be a list [NAME, ARG...]", raw, i, w)
        args = tuple(_expr(rd, item, j, f"{w}[{j}]") for j in range(1, len(item)))
        out.append(Step(item[0], args, line_of(raw, i)))
    return tuple(out)


def _macros(rd: Reader, raw: Any) -> dict[str, Macro]:
    """The macros section."""
    if not isinstance(raw, dict):
        rd.fail("must be a mapping of macro name → {params, steps}", raw, None, "macros")
    out = {}
    for name, body in raw.items():
        w = f"macros.{name}"
        if name in PRIMITIVES or name in GLOBALS:
            rd.fail(f"'{name}' is a built-in name and cannot be a macro", raw, name, w)
        rd.keys(rd.mapping(body, w, raw, name), w, ("params", "steps"), where=w)
        params = rd.names(body, "params", f"{w}.params", where=f"{w}.params")
        for p in params:
            if p in GLOBALS:
                rd.fail(f"parameter '{p}' hides a global name", body, "params", w)
        out[name] = Macro(name, params, _steps(rd, body, "steps", f"{w}.steps"), line_of(raw, name))
    return out


def _operations(rd: Reader, raw: Any) -> dict[str, OperationRule]:
    """The operations section."""
    if not isinstance(raw, dict):
        rd.fail("must be a mapping of operation → {goal, steps}", raw, None, "operations")
    out = {}
    for name, body in raw.items():
        w = f"operations.{name}"
        rd.keys(rd.mapping(body, w, raw, name), w, ("goal", "steps"),
                ("check-jaws", *FINE_MOTIONS), where=w)
        goal = rd.names(body, "goal", f"{w}.goal", GOAL_SOURCES, f"{w}.goal")
        check = rd.boolean(body, "check-jaws", f"{w}.check-jaws", False)
        fine = {k: _steps(rd, body, k, f"{w}.{k}") for k in FINE_MOTIONS if k in body}
        out[name] = OperationRule(name, goal, _steps(rd, body, "steps", f"{w}.steps"),
                                  line_of(raw, name), check, fine)
    return out


def _check_calls(rd: Reader, macros: dict[str, Macro], ops: dict[str, OperationRule],
                 set_aside: tuple[Step, ...] = ()) -> None:
    """Every step names a known macro or primitive with the right arity and known names."""
    def check(steps: tuple[Step, ...], scope: set[str], where: str) -> None:
        for s in steps:
            if s.name in PRIMITIVES:
                arity = len(PRIMITIVES[s.name].args)
            elif s.name in macros:
                arity = len(macros[s.name].params)
            else:
                raise InputError(f"unknown macro or primitive '{s.name}'", file=rd.file,
                                 line=s.line, where=where)
            if len(s.args) != arity:
                raise InputError(f"'{s.name}' takes {arity} argument(s), got {len(s.args)}",
                                 file=rd.file, line=s.line, where=where)
            for a in s.args:
                for n in (a,) if isinstance(a, str) else a:
                    if n not in scope and n not in GLOBALS:
                        raise InputError(f"unknown name '{n}' in the arguments of '{s.name}'",
                                         file=rd.file, line=s.line, where=where)
    for m in macros.values():
        check(m.steps, set(m.params), f"macros.{m.name}")
    for o in ops.values():
        check(o.steps, set(), f"operations.{o.name}")
        for kind, steps in o.fine.items():
            check(steps, set(), f"operations.{o.name}.{kind}")
    check(set_aside, set(), "set-aside")
    _no_recursion(rd, macros)


def _no_recursion(rd: Reader, macros: dict[str, Macro]) -> None:
    """A macro may not (indirectly) expand to itself."""
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for s in macros[name].steps:
            if s.name not in macros:
                continue
            if state.get(s.name) == 1:
                cycle = " → ".join([*path, s.name])
                raise InputError(f"recursive macro expansion {cycle}", file=rd.file,
                                 line=s.line, where=f"macros.{name}")
            if s.name not in state:
                visit(s.name, [*path, s.name])
        state[name] = 2

    for name in macros:
        if name not in state:
            visit(name, [name])
