"""The interface between the interpreter and whatever answers event queries.

ENV-nodes answer an event query by calling the detector method that Table III
names for the event (rules/events.yaml: the event-table of Table II maps an
event to a method, the detector-table a method to a VFD). A *detector
registry* maps detector names to objects implementing ``Detector``. Perception
provides image-based detectors; ``lbw_engine.see.replay`` provides detectors
that read a recorded event trace. Both plug in behind the same protocol; see
docs/engine.md.

Each detector declares its closed vocabulary (``methods`` it answers and the
``answers`` its snapshot comparisons give); the rules map their own words onto
it, so renaming an event or a Table V value is a rule edit.

Lifecycle per frame (Sec. V-A): ``begin_frame`` on every detector, then the
detect passes (``query``), then the analyze step, which at segmentation points
calls ``snapshot`` (start and end of a motion) and ``compare`` (end).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

from lbw_engine.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from lbw_engine.model.env import EnvModel, EnvNode

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class ObjectInfo:
    """An object the object-finder located: shape name, box size and centre (mm)."""

    shape: str
    size: Vec3
    position: Vec3


@dataclass
class Detection:
    """What a detector reports for one query or one snapshot comparison.

    found:     names of ENV-nodes the event concerns (the Locs close to the hand,
               ``hand`` for a newly found moving hand, the objects located).
    value:     a qualitative value (a Table IV motion value, a Table V change
               value such as the change-detector's).
    velocity:  the hand's 3-D velocity in mm/s; the HandLoc node turns it into
               a Table IV value when ``value`` is not given.
    position:  one measured 3-D point (e.g. the centre of a changed area).
    positions: measured 3-D positions of named nodes (e.g. ``hand``).
    objects:   the object-finder's result, name -> ObjectInfo.
    t:         when the event began, if the detector could only confirm it later
               (it looks at a stretch of frames): the segmentation time. Never
               after the current frame; None means the current frame's time.
    """

    found: tuple[str, ...] = ()
    value: Any = None
    velocity: Vec3 | None = None
    position: Vec3 | None = None
    positions: dict[str, Vec3] = field(default_factory=dict)
    objects: dict[str, ObjectInfo] = field(default_factory=dict)
    t: float | None = None


@dataclass(frozen=True)
class Query:
    """What an ATTN-node asks an ENV-node (Sec. V-A "Detect").

    event:  the rules' event name (a replay trace records it);
    method: the detector method the event-table names (the detector's vocabulary);
    base, target: the ENV-nodes the ATTN-node points to;
    since:  the frame on which the ACT-node waiting for the event was made: the stretch
            of the hand's path the query is about (e.g. the hand's descent towards a target).
    """

    event: str
    method: str
    base: tuple[EnvNode, ...]
    target: tuple[EnvNode, ...]
    since: float = 0.0


@dataclass(frozen=True)
class ActView:
    """What a detector may know about the ACT-node a snapshot is taken for.

    ``t`` is the current frame's time; ``since`` the frame the ACT-node was made on.
    """

    motion: str
    base: tuple[str, ...]
    target: tuple[str, ...]
    special: tuple[str, ...]
    t: float
    since: float = 0.0


@runtime_checkable
class Detector(Protocol):
    """One detector (a VFD behind an ENV-node, Table I), as the interpreter sees it."""

    methods: frozenset[str]  # the event methods it answers
    answers: frozenset[Any]  # the values its snapshot comparisons give

    def begin_frame(self, t: float, frame: Any) -> None:
        """A new frame at time ``t`` (seconds) is current; detectors read only it."""

    def query(self, query: Query, env: EnvModel) -> Detection | None:
        """Answer an event query for the current frame: a Detection, or None if not found."""

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """Take a snapshot of the current frame for ``act`` (opaque to the engine)."""

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """The qualitative change between two snapshots (``value``) and where (``position``)."""


class ConstantDetector:
    """The engine's own detector for events that hold at once (Table VII, row 1)."""

    methods: frozenset[str] = frozenset()  # it answers any method: the event holds
    answers: frozenset[Any] = frozenset()

    def begin_frame(self, t: float, frame: Any) -> None:
        """Nothing to read."""

    def query(self, query: Query, env) -> Detection | None:
        """Always reports the event, with nothing found."""
        return Detection()

    def snapshot(self, act: ActView, env) -> Any:
        """No snapshot to take."""
        return None

    def compare(self, first: Any, last: Any, act: ActView, env) -> Detection | None:
        """Nothing changes."""
        return None


BUILTINS = {"constant": ConstantDetector}


class DetectorRegistry:
    """Detector name (from rules/events.yaml) -> Detector."""

    def __init__(self, detectors: Mapping[str, Detector]) -> None:
        self._detectors = dict(detectors)

    @classmethod
    def for_rules(cls, rules, provided: Mapping[str, Detector]) -> DetectorRegistry:
        """Registry for every detector the rules name: builtins plus ``provided``."""
        out: dict[str, Detector] = {}
        for name, spec in rules.detectors.items():
            if spec.builtin:
                out[name] = BUILTINS[spec.builtin]()
            elif name in provided:
                out[name] = provided[name]
            else:
                raise spec.at.error(f"detector {name!r} has no implementation in this registry")
        return cls(out)

    def __getitem__(self, name: str) -> Detector:
        """The detector called ``name``."""
        try:
            return self._detectors[name]
        except KeyError:
            raise InputError(f"no detector called {name!r} is registered") from None

    def unique(self) -> Iterable[Detector]:
        """Each registered detector object once (one object may serve several names)."""
        seen: list[int] = []
        for det in self._detectors.values():
            if id(det) not in seen:
                seen.append(id(det))
                yield det

    def vocabulary(self) -> dict[str, dict[str, frozenset]]:
        """Detector name -> the methods it answers and the answers it gives."""
        return {name: {"methods": frozenset(getattr(det, "methods", ())),
                       "answers": frozenset(getattr(det, "answers", ()))}
                for name, det in self._detectors.items()}

    def begin_frame(self, t: float, frame: Any) -> None:
        """Tell every detector that a new frame is current."""
        for det in self.unique():
            det.begin_frame(t, frame)
