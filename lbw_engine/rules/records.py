"""Typed records of the recognition rule files (Tables III-VIII, Sec. V-B4).

Every name the interpreter uses (events, detectors, motion classes, features,
operations, relations) comes from these records; ``RuleSet`` bundles them with
the analysis and command rules (``lbw_engine.rules.load_rules``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError

# Slot bindings understood by the interpreter (a closed vocabulary; Table VII
# "new base"/"new target" and Table VIII "base"/"target" columns).
BINDINGS = ("base", "target", "special", "found", "held", "hand", "world", "table", "none")
SLOTS = ("base", "target", "special")
DIRECTIONS = ("next", "down", "up", "none")
STACK_OPS = ("add", "reset", "delete")
FEATURE_SOURCES = ("final-event", "hand-holds", "snapshot-diff", "target-kind", "support-kind")
# The slots a snapshot-diff feature's detector may name the nodes of (``names``).
NAMED_SLOTS = ("target",)
SPEED_TESTS = ("slow", "within", "fast")
DIRECTION_TESTS = ("up", "down", "lateral")
INIT = "init"
RULE_FILES = (
    "events.yaml",
    "motion-features.yaml",
    "motions.yaml",
    "operations.yaml",
    "effects.yaml",
    "transitions.yaml",
    "attention.yaml",
    "constants.yaml",
    "analysis.yaml",
    "templates.lark",
    "plot.lark",
    "commands.yaml",
    "domain.yaml",
)

Binding = tuple[str, ...]  # alternatives: the first that resolves to nodes wins


@dataclass(frozen=True)
class Where:
    """A place in a rule file, for error messages."""

    file: str
    line: int | None

    def error(self, message: str, where: str | None = None) -> InputError:
        """An InputError at this place."""
        return InputError(message, file=self.file, line=self.line, where=where)


@dataclass(frozen=True)
class DetectorDef:
    """A detector named by Table III; ``builtin`` ones are answered by the engine."""

    name: str
    builtin: str | None
    at: Where


@dataclass(frozen=True)
class EventDef:
    """One row of Table III, with the detector method that answers it (Table II)."""

    name: str
    meaning: str
    detector: str
    method: str
    nodes: tuple[str, ...]
    at: Where


@dataclass(frozen=True)
class FeatureValueRow:
    """One row of Table IV."""

    value: str
    speed: str
    direction: str | None
    at: Where


@dataclass(frozen=True)
class MotionFeatures:
    """Table IV with the thresholds of footnote 11."""

    ranges: dict[str, tuple[float, float]]
    angle_down: float
    angle_up: float
    rows: tuple[FeatureValueRow, ...]

    def values(self) -> tuple[str, ...]:
        """All qualitative values, in table order."""
        return tuple(r.value for r in self.rows)


@dataclass(frozen=True)
class MotionClass:
    """An assembly motion class of Fig. 9 and its attention-stack level."""

    name: str
    level: int
    start: bool
    root: bool
    fine: bool
    at: Where


@dataclass(frozen=True)
class FeatureDef:
    """A Table V feature type and where its value comes from.

    ``answers`` maps each value of a snapshot-diff feature to the detector's own
    answer (its closed vocabulary); ``value_of`` reads an answer back. ``names`` is the
    slot whose nodes the detector's comparison may name instead (the block that
    really left with the hand), None if its named nodes change no slot.
    """

    name: str
    source: str
    detector: str | None
    values: tuple[Any, ...]
    kinds: dict[str, str]
    at: Where
    answers: dict[Any, Any] = field(default_factory=dict)
    names: str | None = None  # the slot the detector's named nodes replace (NAMED_SLOTS)

    def value_of(self, answer: Any) -> Any:
        """The feature value a detector's answer stands for (None if it names none)."""
        for value, said in self.answers.items():
            if said == answer and type(said) is type(answer):
                return value
        return None


@dataclass(frozen=True)
class ClassRow:
    """One row of Table V: when all feature values match, the operation."""

    motion: str
    when: dict[str, Any]
    operation: str
    at: Where
    label: str | None = None  # name stem in sequences (Fig. 12 "no01"); default: lower case


@dataclass(frozen=True)
class TransitionRow:
    """One row of Table VII."""

    motion: str
    key: str
    direction: str
    next: str | None
    slots: dict[str, Binding]
    close_target: Binding | None
    at: Where


@dataclass(frozen=True)
class RedirectionRow:
    """One row of Table VIII."""

    motion: str
    key: str
    op: str
    event: str | None
    base: Binding
    target: Binding
    at: Where


@dataclass(frozen=True)
class Template:
    """A relation template of effects.yaml: [type, subject, object, {wrt: ...}]."""

    type: str
    subject: str
    object: str
    wrt: str | None
    when: tuple[str, str] | None  # ("single" | "multiple", variable)
    at: Where


@dataclass(frozen=True)
class EffectRule:
    """What one operation changes in the environment model (Sec. V-B4)."""

    operation: str
    bind: dict[str, Any]
    remove: tuple[Template, ...]
    add: tuple[Template, ...]
    move: dict[str, str]
    at: Where


@dataclass(frozen=True)
class Roles:
    """The relations named by role in effects.yaml: holding, and single / multiple support."""

    hold: str
    single: str
    multiple: str

    @property
    def support(self) -> tuple[str, str]:
        """The support relations (single, multiple)."""
        return (self.single, self.multiple)


@dataclass
class RuleSet:
    """Everything in rules/, checked."""

    directory: Path
    detectors: dict[str, DetectorDef]
    events: dict[str, EventDef]
    motion_features: MotionFeatures
    motions: dict[str, MotionClass]
    features: dict[str, FeatureDef]
    classification: dict[str, tuple[ClassRow, ...]]
    relations: tuple[str, ...]
    roles: Roles
    effects: dict[str, EffectRule]
    transitions: dict[tuple[str, str], TransitionRow]
    redirections: dict[str, tuple[RedirectionRow, ...]]
    constants: dict[str, Any]
    operations: set[str] = field(default_factory=set)
    analysis: Any = None  # lbw_engine.rules.analysis.AnalysisRules
    commands: Any = None  # lbw_engine.rules.commands.CommandRules
    domain: Any = None  # lbw_engine.rules.domain.Domain (preconditions and effects)

    @property
    def hold_relation(self) -> str:
        """The relation by which the hand holds an object."""
        return self.roles.hold

    @property
    def support_relations(self) -> tuple[str, str]:
        """The support relations: (single, multiple)."""
        return self.roles.support

    def labels(self) -> dict[str, str]:
        """Leaf label (Fig. 12's ``no`` of no01) -> operation, for every operation."""
        out: dict[str, str] = {}
        for rows in self.classification.values():
            for row in rows:
                out.setdefault(self.label(row.motion, row.operation), row.operation)
        return out

    def start_motion(self) -> MotionClass:
        """The class instantiated at cold boot."""
        return next(m for m in self.motions.values() if m.start)

    def interpretation(
        self, motion: str, keys: tuple[str, ...]
    ) -> tuple[TransitionRow | None, list[RedirectionRow]]:
        """Table VII + VIII: the transition and redirections for the first matching key."""
        for key in keys:
            transition = self.transitions.get((motion, key))
            redirections = [r for r in self.redirections.get(motion, ()) if r.key == key]
            if transition or redirections:
                return transition, redirections
        return None, []

    def label(self, motion: str, operation: str | None) -> str:
        """Stem of an operation's name in a recognized sequence (Fig. 12)."""
        for row in self.classification.get(motion, ()):
            if row.operation == operation and row.label:
                return row.label
        return (operation or "unclassified").lower()

    def init_redirections(self, motion: str) -> list[RedirectionRow]:
        """The :Init rows of Table VIII for a motion class."""
        return [r for r in self.redirections.get(motion, ()) if r.key == INIT]

    def snapshot_detectors(self, motion: str) -> tuple[str, ...]:
        """Detectors whose snapshots Table V needs at a motion's start and end."""
        names: list[str] = []
        for row in self.classification.get(motion, ()):
            for feature in row.when:
                spec = self.features[feature]
                if spec.source == "snapshot-diff" and spec.detector not in names:
                    names.append(spec.detector)
        return tuple(names)
