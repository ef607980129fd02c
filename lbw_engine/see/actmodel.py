"""ACT-nodes (Table VI), slot bindings (Tables VII, VIII) and classification (Table V)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from lbw_engine.model.env import EnvModel, State
from lbw_engine.names import HAND, TABLE, WORLD
from lbw_engine.rules import Binding, RuleSet
from lbw_engine.see.detectors import ActView, Detection


@dataclass(eq=False)
class ActNode:
    """An instantiated assembly motion: the slots of Table VI."""

    motion: str
    name: str
    level: int
    parent: ActNode | None
    base: tuple[str, ...] = ()
    target: tuple[str, ...] = ()
    special: tuple[str, ...] = ()
    subnode: ActNode | None = None
    history: list[ActNode] = field(default_factory=list)
    initial_event: str | None = None
    final_event: str | None = None
    t_start: float = 0.0  # the segmentation time (a detector may date an event back)
    t_end: float | None = None
    t_created: float = 0.0  # the frame the recognizer made this node on
    initial_state: State | None = None
    final_state: State | None = None
    operation: str | None = None
    snapshots: dict[str, Any] = field(default_factory=dict)  # detector -> first snapshot
    features: dict[str, Any] = field(default_factory=dict)
    measured: dict[str, Any] = field(default_factory=dict)  # feature -> measured position
    found_by: dict[str, tuple[str, ...]] = field(default_factory=dict)  # feature -> names
    bound: dict[str, tuple[str, ...]] = field(default_factory=dict)  # effect variable -> names
    # The Table VII row, the ending node and the detection this node was made from by a
    # :next transition: its slots are bound again if that node is classified late.
    origin: tuple[Any, ActNode, Detection | None] | None = None

    def slot(self, name: str) -> tuple[str, ...]:
        """The names in slot ``name`` (base, target or special)."""
        return getattr(self, name)

    def nodes(self) -> list[str]:
        """ENV-node names this ACT-node concerns (for its state copies)."""
        return list(dict.fromkeys((*self.base, *self.target, *self.special)))

    def view(self, t: float) -> ActView:
        """What a detector may know about this node."""
        return ActView(self.motion, self.base, self.target, self.special, t, self.t_created)


def resolve(
    binding: Binding, node: ActNode, env: EnvModel, detection: Detection | None = None
) -> tuple[str, ...]:
    """The ENV-node names a binding stands for: the first alternative that is not empty."""
    for name in binding:
        if name in ("base", "target", "special"):
            names = node.slot(name)
        elif name == "found":
            names = tuple(n for n in (detection.found if detection else ()) if n in env.nodes)
        elif name == "held":
            names = env.held(HAND)
        elif name == "hand":
            names = (HAND,)
        elif name == "world":
            names = (WORLD,)
        elif name == "table":
            names = (TABLE,)
        else:  # "none"
            names = ()
        if names:
            return tuple(names)
    return ()


def compute_features(
    rules: RuleSet, node: ActNode, event: str | None, env: EnvModel, compared: dict[str, Any]
) -> dict[str, Any]:
    """Table V feature values of ``node`` at its end; ``compared`` holds detector diffs.

    Snapshot diffs come first: a detector may name the node's real target (``names``),
    and the target's kind must be read from that."""
    out: dict[str, Any] = {}
    ordered = sorted(rules.features.items(), key=lambda item: item[1].source != "snapshot-diff")
    for name, spec in ordered:
        if spec.source == "final-event":
            out[name] = event
        elif spec.source == "hand-holds":
            out[name] = bool(env.held(HAND))
        elif spec.source == "snapshot-diff":
            diff = compared.get(spec.detector)
            if diff is not None:
                out[name] = spec.value_of(diff.value)  # the detector's answer, in rule words
                node.measured[name] = diff.position
                node.found_by[name] = tuple(diff.found)
                named = tuple(n for n in diff.found if n in env.nodes)
                if spec.names is not None and named:
                    _rename(node, spec.names, named)
        else:  # target-kind, or support-kind: the kind of what the targets rest on
            targets = env.get(node.target)
            if spec.source == "support-kind":
                targets = env.get(s for n in targets for s in env.supports_of(n.name))
            kinds = {spec.kinds.get(n.kind) for n in targets}
            out[name] = kinds.pop() if len(kinds) == 1 else None
    return out


def _rename(node: ActNode, slot: str, named: tuple[str, ...]) -> None:
    """Set ``node``'s ``slot`` to what a detector named, and the same slot of the motion just
    before it when that held the same mistaken names: the motion that came to the node
    was after what the node acted on (the hand came down over a knob riding on a slat,
    and the next motion lifted the slat: it came for the slat, bench rearrange
    1213)."""
    old = node.slot(slot)
    setattr(node, slot, named)
    siblings = node.parent.history if node.parent is not None else []
    before = siblings[:siblings.index(node)] if node in siblings else siblings
    if old and old != named and before and before[-1].slot(slot) == old:
        setattr(before[-1], slot, named)


def classify(rules: RuleSet, motion: str, features: dict[str, Any]) -> str | None:
    """Table V: the operation of the first row whose feature values all match."""
    for row in rules.classification.get(motion, ()):
        if all(features.get(k) == v for k, v in row.when.items()):
            return row.operation
    return None


def effect_bindings(rules: RuleSet, node: ActNode, env: EnvModel) -> dict[str, tuple[str, ...]]:
    """Variables of the operation's effect rule, from the node's slots (effects.yaml)."""
    rule = rules.effects[node.operation]
    out: dict[str, tuple[str, ...]] = {}
    for var, spec in rule.bind.items():
        if isinstance(spec, dict) and "found" in spec:
            # the ENV-nodes the feature's detector named (e.g. the block a face lines up
            # with), else a slot (a detector that names none, e.g. a replayed trace)
            named = tuple(n for n in node.found_by.get(spec["found"], ()) if n in env.nodes)
            out[var] = named or resolve((spec["else"],), node, env)
        elif isinstance(spec, dict):
            names = resolve((spec["nearest"],), node, env)
            point = node.measured.get(spec["to"])
            out[var] = _nearest(names, point, env)
        else:
            out[var] = resolve((spec,), node, env)
    return out


def _nearest(names: tuple[str, ...], point: Any, env: EnvModel) -> tuple[str, ...]:
    """The one name whose node is closest to ``point`` (the first if unmeasured)."""
    if len(names) <= 1 or point is None:
        return names[:1]

    def distance(name: str) -> float:
        pos = env.nodes[name].position
        return math.dist(pos, point) if pos is not None else math.inf

    return (min(names, key=distance),)
