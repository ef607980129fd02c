"""The rule set: typed records of rules/*.yaml, loaded and cross-checked at once.

Every name the interpreter uses (events, detectors, motion classes, features,
operations, relations) comes from these files; nothing runs until all of them
load and agree. Per-file parsing lives in ``rulefiles``; this module defines
the records and the checks that span files (references and rows that can
never fire).
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
FEATURE_SOURCES = ("final-event", "holding", "snapshot-diff", "target-kind", "support-kind")
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
    """One row of Table III."""

    name: str
    meaning: str
    detector: str
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
    """A Table V feature type and where its value comes from."""

    name: str
    source: str
    detector: str | None
    values: tuple[Any, ...]
    kinds: dict[str, str]
    at: Where


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
    hold_relation: str
    support_relations: tuple[str, ...]
    effects: dict[str, EffectRule]
    transitions: dict[tuple[str, str], TransitionRow]
    redirections: dict[str, tuple[RedirectionRow, ...]]
    constants: dict[str, Any]
    operations: set[str] = field(default_factory=set)

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


def load_rules(directory: str | Path | None = None) -> RuleSet:
    """Load and check every rule file of ``directory`` (default: the bundled rules)."""
    from lbw_engine.paths import default_rules_dir
    from lbw_engine.rules import check as rulecheck
    from lbw_engine.rules import files as rulefiles

    directory = Path(directory) if directory is not None else default_rules_dir()
    if not directory.exists():
        raise InputError("rules folder not found", file=directory)
    if not directory.is_dir():
        raise InputError("is not a folder of rule files", file=directory)
    rules = rulefiles.read_all(directory)
    rulecheck.check(rules)
    return rules
