"""The detect-analyze loop of Sec. V-A, driven frame by frame by the rules.

For each frame: every detector gets ``begin_frame``; then detect passes ask
each ATTN-node not yet asked in this frame (bottom to top) and the analyze
step interprets recorded events bottom to top (Tables VII, VIII). ATTN-nodes
placed by an analyze step are asked in a further pass of the same frame, up to
``detect-passes-per-frame`` (rules/constants.yaml). The order of steps is
tabulated in docs/engine.md.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from typing import Any

from lbw_engine.model.effects import apply_effect
from lbw_engine.model.env import EnvModel
from lbw_engine.names import WORLD
from lbw_engine.rules import RedirectionRow, RuleSet, TransitionRow
from lbw_engine.see import actmodel
from lbw_engine.see.actmodel import ActNode
from lbw_engine.see.attention import AttentionStack, AttnNode
from lbw_engine.see.detectors import Detection, DetectorRegistry, Query
from lbw_engine.see.motionfeatures import classify as motion_value


class Recognizer:
    """Action recognizer: action model, environment model and attention stack (Fig. 7)."""

    def __init__(self, rules: RuleSet, registry: DetectorRegistry, env: EnvModel | None = None):
        self.rules = rules
        self.registry = registry
        self.env = env if env is not None else EnvModel(rules)
        self.stack = AttentionStack()
        self.counts: Counter[str] = Counter()
        self.t = 0.0
        self.t_seg = 0.0  # segmentation time of the event being interpreted
        self.root: ActNode | None = None
        self.finished = False
        self.initial_objects: dict[str, dict[str, Any]] = {}
        self.log: list[tuple[float, str, str, Any]] = []  # (t, motion, event, value)
        # Ended motions whose end state a snapshot detector cannot judge yet (the hand
        # hides it): classified on a later frame, at the latest when their parent ends.
        self.deferred: list[ActNode] = []
        start = rules.start_motion()
        self._create(start.name, None, start.level, {"base": (WORLD,)}, None)

    # --- the loop -------------------------------------------------------------
    def run(self, frames: Iterable[tuple[float, Any]]) -> ActNode | None:
        """Feed (t, frame) pairs in time order; finish; return the root ACT-node."""
        for t, frame in frames:
            if self.finished:
                break
            self.step(t, frame)
        self.finish()
        return self.root

    def step(self, t: float, frame: Any = None) -> None:
        """One frame: detect passes alternating with analyze steps (Sec. V-A)."""
        self.t = self.t_seg = t
        self.registry.begin_frame(t, frame)
        if self.deferred:
            self._settle_deferred(None)
        for node in self.stack.scan():
            node.asked = False
        for _ in range(int(self.rules.constants["detect-passes-per-frame"])):
            fresh = [n for n in self.stack.scan() if not n.asked]
            if not fresh or self.finished:
                return
            for node in fresh:  # 1) detect: bottom to top
                node.asked = True
                node.detection = self._query(node)
            self._analyze()  # 2) analyze: bottom to top

    def finish(self) -> None:
        """End of input: close the motions still open, without a final event."""
        if not self.finished and self.root is not None:
            self.t_seg = self.t
            self._terminate(self.root, None)
            self.stack.reset(0)
            self.finished = True

    # --- detect -----------------------------------------------------------------
    def _query(self, node: AttnNode) -> Detection | None:
        """Send the ATTN-node's event query to the ENV-node's detector (Table III)."""
        spec = self.rules.events[node.event]
        detector = self.registry[spec.detector]
        query = Query(node.event, spec.method, tuple(self.env.get(node.base)),
                      tuple(self.env.get(node.target)), node.owner.t_created)
        found = detector.query(query, self.env)
        if found is None:
            return None
        ranges = self.rules.motion_features.ranges
        if found.value is None and found.velocity is not None and node.event in ranges:
            # The HandLoc node turns a velocity into a Table IV value (Sec. IV-A).
            found.value = motion_value(found.velocity, node.event, self.rules.motion_features)
        if found.objects:
            for name, info in found.objects.items():
                self.initial_objects[name] = {"shape": info.shape, "position": list(info.position)}
        self._absorb(found)
        return found

    def _absorb(self, found: Detection) -> None:
        """Put what a detection measured into the environment model (located objects,
        positions of named nodes such as the hand)."""
        if found.objects:
            self.env.locate((name, info.shape, info.size, info.position)
                            for name, info in found.objects.items())
        for name, pos in found.positions.items():
            if name in self.env.nodes:
                self.env.move_node(name, tuple(float(v) for v in pos))

    # --- analyze ----------------------------------------------------------------
    def _analyze(self) -> None:
        """Interpret recorded events, lowest stack level first."""
        while not self.finished:
            node = next((n for n in self.stack.scan() if n.detection is not None), None)
            if node is None:
                return
            detection, node.detection = node.detection, None
            self._interpret(node, detection)

    def _interpret(self, attn: AttnNode, detection: Detection) -> None:
        """Table VII transition, then Table VIII redirections, for one event."""
        act = attn.owner
        keys = (attn.event,)
        if isinstance(detection.value, str):
            keys = (attn.event, detection.value)
        self.log.append((self.t, act.motion, attn.event, detection.value))
        # Segmentation time: the event's onset when the detector dates it (a detector
        # that watches a stretch of frames confirms an event after it began), never
        # before the receiving motion started nor after this frame.
        self.t_seg = self.t if detection.t is None else min(self.t, max(act.t_start, detection.t))
        transition, redirections = self.rules.interpretation(act.motion, keys)
        if transition is not None:
            self._transit(act, transition, attn.event, detection)
        for row in redirections:
            self._redirect(act, row, attn, detection)

    def _transit(self, act: ActNode, row: TransitionRow, event: str, detection: Detection) -> None:
        """Execute an action transition specification (:next, :down, :up or none)."""
        if row.direction == "none":
            for slot, binding in row.slots.items():
                setattr(act, slot, actmodel.resolve(binding, act, self.env, detection))
            return
        if row.direction == "up":
            self._terminate(act, event)
            if act.parent is not None:
                act.parent.subnode = None
            self.stack.reset(act.level)
            self.finished = act.parent is None
            return
        if row.close_target is not None:
            closing = actmodel.resolve(row.close_target, act, self.env, detection)
            if closing:
                act.target = closing
        if row.direction == "next":
            parent, level = act.parent, act.level
            self._terminate(act, event)
        else:  # "down": a subnode of the receiving node; an old one ends first
            parent, level = act, act.level + 1
            if act.subnode is not None:
                self._terminate(act.subnode, event)
        node = self._create(row.next, parent, level, self._bind(row, act, detection), event)
        if row.direction == "next":
            node.origin = (row, act, detection)

    def _bind(self, row: TransitionRow, act: ActNode, detection: Detection | None
              ) -> dict[str, tuple[str, ...]]:
        """The next ACT-node's slots by a transition row (a slot left out: ``act``'s)."""
        return {
            slot: actmodel.resolve(row.slots[slot], act, self.env, detection)
            if slot in row.slots
            else act.slot(slot)
            for slot in ("base", "target", "special")
        }

    def _redirect(
        self, act: ActNode, row: RedirectionRow, attn: AttnNode | None, detection: Detection | None
    ) -> None:
        """Execute one attention redirection at the ACT-node's level (Table VIII)."""
        if row.op == "delete":
            self.stack.delete(act.level, node=attn if row.event is None else None, event=row.event)
            return
        new = AttnNode(
            row.event,
            actmodel.resolve(row.base, act, self.env, detection),
            actmodel.resolve(row.target, act, self.env, detection),
            act,
        )
        if row.op == "add":
            self.stack.add(act.level, new)
        else:
            self.stack.reset(act.level, new)

    # --- segmentation -----------------------------------------------------------
    def _create(
        self,
        motion: str,
        parent: ActNode | None,
        level: int,
        slots: dict[str, tuple[str, ...]],
        event: str | None,
    ) -> ActNode:
        """Instantiate an ACT-node, copy its initial state, take its first snapshots."""
        self.counts[motion] += 1
        node = ActNode(
            motion,
            f"{motion}{self.counts[motion]}",
            level,
            parent,
            t_start=self.t_seg,
            t_created=self.t,
            initial_event=event,
            **slots,
        )
        if parent is not None:
            parent.subnode = node
        if self.rules.motions[motion].root:
            self.root = node
        # Copy every node now: some motions learn their target only as they end, and
        # IS and FS must describe the same ENV-nodes (Table VI), so the copy is
        # cut down to the node's final base/target/special in _terminate.
        node.initial_state = self.env.snapshot(self.env.nodes)
        for name in self.rules.snapshot_detectors(motion):
            node.snapshots[name] = self.registry[name].snapshot(node.view(self.t), self.env)
        # Automatic :reset of the new node's level with its :Init redirections (Sec. IV-B3).
        self.stack.reset(level)
        for row in self.rules.init_redirections(motion):
            self._redirect(node, row, None, None)
        return node

    def _terminate(self, node: ActNode, event: str | None) -> None:
        """End a motion: close its subnode, classify it, update the env, store it.

        If a snapshot detector cannot judge the motion's end state yet, the motion
        still ends now (segmentation) but its classification waits for a later frame
        (frames stay in order: it uses no frame after the one it is decided on). A
        motion is classified after every earlier motion of its parent: effects change
        the environment model in the order the motions happened.
        """
        if node.subnode is not None:
            self._terminate(node.subnode, event)
            node.subnode = None
        self._settle_deferred(node)
        self._settle_deferred(node.parent, before=node)
        lasts = self._last_snapshots(node)
        node.final_event, node.t_end = event, self.t_seg
        if node.parent is not None:
            node.parent.history.append(node)
            if self._pending(lasts):
                self.deferred.append(node)
                return
        self._classify(node, lasts)

    def _last_snapshots(self, node: ActNode) -> dict[str, Any]:
        """Each snapshot detector's snapshot of the current frame for ``node``."""
        view = node.view(self.t)
        return {name: self.registry[name].snapshot(view, self.env) for name in node.snapshots}

    def _pending(self, lasts: dict[str, Any]) -> bool:
        """Whether some detector says its snapshot cannot be judged yet (optional ``pending``)."""
        for name, last in lasts.items():
            pending = getattr(self.registry[name], "pending", None)
            if pending is not None and pending(last):
                return True
        return False

    def _settle_deferred(self, parent: ActNode | None, before: ActNode | None = None) -> None:
        """Classify deferred motions that can be judged now; those of ``parent`` in any case
        (with ``before``: only those that ended before it, its earlier siblings).

        A motion made by a :next transition from one classified late had its slots
        bound from the environment model before that one's effect: those are bound
        again, and its initial state copied again (a motion begun while the one
        before it waited to be judged still named the block set down there).
        """
        for node in list(self.deferred):
            forced = parent is not None and node.parent is parent and node is not before
            lasts = self._last_snapshots(node)
            if forced or not self._pending(lasts):
                self.deferred.remove(node)
                self._classify(node, lasts)
                self._rebind_successor(node)

    def _rebind_successor(self, node: ActNode) -> None:
        """Bind again the slots of the open motion made from ``node`` (see above)."""
        after = node.parent.subnode if node.parent is not None else None
        if after is None or after.origin is None or after.origin[1] is not node:
            return
        row, _, detection = after.origin
        # only slots bound from the environment model (``held``): the others may have
        # been set since (a target closed to what the motion's ending event found)
        for slot, binding in row.slots.items():
            if "held" in binding:
                setattr(after, slot, actmodel.resolve(binding, node, self.env, detection))
        after.initial_state = self.env.snapshot(self.env.nodes)

    def _classify(self, node: ActNode, lasts: dict[str, Any]) -> None:
        """Features (Table V) from the snapshot comparisons, the operation, its effect, FS."""
        compared = {}
        view = node.view(self.t)
        for name, first in node.snapshots.items():
            compared[name] = self.registry[name].compare(first, lasts[name], view, self.env)
        node.features = actmodel.compute_features(self.rules, node, node.final_event, self.env,
                                                  compared)
        node.operation = actmodel.classify(self.rules, node.motion, node.features)
        if node.operation in self.rules.effects:
            node.bound = binds = actmodel.effect_bindings(self.rules, node, self.env)
            apply_effect(self.env, self.rules.effects[node.operation], binds, node.measured)
            for found in compared.values():  # where a comparison measured a held object now
                for name, pos in (found.positions if found is not None else {}).items():
                    if name in self.env.held():
                        self.env.hang(name, pos)
        node.final_state = self.env.snapshot(node.nodes())
        if node.initial_state is not None:
            node.initial_state = node.initial_state.restricted(self.env.copied(node.nodes()))
