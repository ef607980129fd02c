"""The environment model (Sec. IV-A): ENV-nodes, their positions and relations.

Nodes are of the ENV classes of Fig. 8: one World, one HandLoc (``hand``),
one Table (``table``) and one Loc per object. Relations are
(type, subject, object[, at, wrt]) records; ``at`` is the subject's position
relative to the ``wrt`` node (Fig. 14, Fig. 21). Operation effects come from
rules/effects.yaml as relation templates (``apply_effect``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from lbw_engine.rules import EffectRule, RuleSet, Template
from lbw_engine.see.detectors import Detection, Vec3

WORLD, HAND, TABLE = "world", "hand", "table"
SUPPORT_OVERLAP_MM = 3.0  # a placed block rests on what is under it by more than this
TABLE_SIZE: Vec3 = (600.0, 400.0, 0.0)  # design.md workspace; the top face is z = 0


@dataclass
class EnvNode:
    """An ENV-node: a named region of the workspace (Table II slots we use)."""

    name: str
    kind: str  # "World" | "HandLoc" | "Table" | "Loc"
    position: Vec3 | None = None
    size: Vec3 | None = None
    shape: str | None = None

    def top(self) -> float:
        """Height of the node's top face (mm)."""
        if self.position is None or self.size is None:
            return 0.0
        return self.position[2] + self.size[2] / 2.0


@dataclass(frozen=True)
class Relation:
    """A relation between ENV-nodes; ``obj`` is a tuple for several objects."""

    type: str
    subject: str
    obj: str | tuple[str, ...]
    at: Vec3 | None = None
    wrt: str | None = None

    def to_json(self) -> list[Any]:
        """The actions.json form: [type, subject, object] or with {"at", "wrt"}."""
        obj = list(self.obj) if isinstance(self.obj, tuple) else self.obj
        out: list[Any] = [self.type, self.subject, obj]
        if self.at is not None:
            out.append({"at": [round(c, 1) for c in self.at], "wrt": self.wrt})
        return out


@dataclass
class State:
    """A snapshot copy of some ENV-nodes: their relations and positions."""

    relations: list[Relation]
    positions: dict[str, Vec3]

    def restricted(self, names: Iterable[str]) -> State:
        """The part of this copy that concerns ``names`` (relations by subject)."""
        keep = set(names)
        return State([r for r in self.relations if r.subject in keep],
                     {n: p for n, p in self.positions.items() if n in keep})

    def to_json(self) -> dict[str, Any]:
        """The actions.json form of a state."""
        return {
            "relations": [r.to_json() for r in self.relations],
            "positions": {n: [round(c, 1) for c in p] for n, p in self.positions.items()},
        }


def _sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@dataclass
class EnvModel:
    """The ENV-nodes of one workspace and the relations among them."""

    rules: RuleSet
    nodes: dict[str, EnvNode] = field(default_factory=dict)
    relations: list[Relation] = field(default_factory=list)
    followers: dict[str, Vec3] = field(default_factory=dict)  # name -> offset from the hand

    def __post_init__(self) -> None:
        region = tuple(float(v) for v in self.rules.constants["attention-region"])
        self.nodes.setdefault(WORLD, EnvNode(WORLD, "World"))
        self.nodes.setdefault(HAND, EnvNode(HAND, "HandLoc", size=region))
        self.nodes.setdefault(TABLE, EnvNode(TABLE, "Table", (0.0, 0.0, 0.0), TABLE_SIZE))

    # --- lookup -----------------------------------------------------------
    def get(self, names: Iterable[str]) -> list[EnvNode]:
        """The nodes called ``names`` (unknown names are skipped)."""
        return [self.nodes[n] for n in names if n in self.nodes]

    def objects(self) -> list[EnvNode]:
        """The Loc nodes, in the order they were located."""
        return [n for n in self.nodes.values() if n.kind == "Loc"]

    def held(self, hand: str = HAND) -> tuple[str, ...]:
        """What ``hand`` holds, by the hold relation of rules/effects.yaml."""
        return tuple(
            r.obj
            for r in self.relations
            if r.type == self.rules.hold_relation and r.subject == hand and isinstance(r.obj, str)
        )

    def nodes_intersecting(self, center: Sequence[float], size: Sequence[float]) -> list[EnvNode]:
        """Loc nodes whose box meets the box at ``center`` of ``size`` (Sec. III-E step 3)."""
        out = []
        for node in self.objects():
            if node.position is None or node.size is None:
                continue
            if all(
                abs(node.position[i] - center[i]) <= (node.size[i] + size[i]) / 2.0
                for i in range(3)
            ):
                out.append(node)
        return out

    def supports_of(self, name: str) -> list[str]:
        """What ``name`` rests on, by the support relations of the rules."""
        out: list[str] = []
        for r in self.relations:
            if r.type in self.rules.support_relations and r.subject == name:
                out.extend(r.obj if isinstance(r.obj, tuple) else (r.obj,))
        return out

    def supported_by(self, name: str) -> list[str]:
        """Objects resting on ``name``, directly or through others (they ride along)."""
        out: list[str] = []
        todo = [name]
        while todo:
            below = todo.pop()
            for r in self.relations:
                if r.type not in self.rules.support_relations or r.subject in out:
                    continue
                objs = r.obj if isinstance(r.obj, tuple) else (r.obj,)
                if below in objs and r.subject != name:
                    out.append(r.subject)
                    todo.append(r.subject)
        return out

    # --- updates from detections ----------------------------------------------
    def absorb(self, detection: Detection) -> None:
        """Register located objects and measured positions from a detection."""
        for name, info in detection.objects.items():
            size = tuple(float(v) for v in info.size)
            pos = tuple(float(v) for v in info.position)
            self.nodes[name] = EnvNode(name, "Loc", pos, size, info.shape)
        if detection.objects:
            self.initial_relations()
        for name, pos in detection.positions.items():
            if name in self.nodes:
                self.move_node(name, tuple(float(v) for v in pos))

    def move_node(self, name: str, pos: Vec3) -> None:
        """Set a node's position; objects following the hand come along."""
        self.nodes[name].position = pos
        if name == HAND:
            for follower, offset in self.followers.items():
                self.nodes[follower].position = _add(pos, offset)

    def initial_relations(self) -> None:
        """Each located object rests on what is just below it, else on the table.

        The relation is the first support relation of the rules; support is read
        from the measured boxes: a top face within 10 mm of the object's bottom
        face, overlapping it seen from above.
        """
        support = self.rules.support_relations[0]
        for node in self.objects():
            if any(r.subject == node.name for r in self.relations) or node.position is None:
                continue
            below = self._resting_on(node)
            wrt = self.nodes[below]
            at = _sub(node.position, wrt.position) if wrt.position else node.position
            self.relations.append(Relation(support, node.name, below, at, below))

    def _resting_on(self, node: EnvNode) -> str:
        """The object whose top face carries ``node``, or the table."""
        bottom = node.position[2] - (node.size[2] if node.size else 0.0) / 2.0
        best, gap = TABLE, 10.0
        for other in self.objects():
            if other is node or other.position is None or other.size is None:
                continue
            overlap = all(
                abs(node.position[i] - other.position[i]) < (node.size[i] + other.size[i]) / 2.0
                for i in range(2)
            )
            if overlap and abs(other.top() - bottom) <= gap:
                best, gap = other.name, abs(other.top() - bottom)
        return best

    # --- snapshots ---------------------------------------------------------------
    def copied(self, names: Iterable[str]) -> list[str]:
        """The nodes a state copy of ``names`` covers: they and what rests on them.

        Table VI copies an ACT-node's ENV-nodes with their subnode links (Fig. 8:
        supporting, holding), so the blocks riding on a moved plank are part of
        its state: Fig. 14's SI keeps them on the plank, which is what makes the
        plank's ACHIEVE a PACHIEVE. The table's riders (the whole workspace) are
        not followed.
        """
        names = [n for n in dict.fromkeys(names) if n in self.nodes and n != WORLD]
        riders = [r for n in names if self.nodes[n].kind == "Loc" for r in self.supported_by(n)]
        return list(dict.fromkeys([*names, *riders]))

    def snapshot(self, names: Iterable[str]) -> State:
        """Copies of the named nodes' relations and positions (ACT-node IS/FS)."""
        names = self.copied(names)
        rels = [replace(r) for r in self.relations if r.subject in names]
        positions = {n: self.nodes[n].position for n in names if self.nodes[n].position}
        return State(rels, positions)

    # --- operation effects (Sec. V-B4) ------------------------------------------
    def apply_effect(
        self, rule: EffectRule, binds: dict[str, tuple[str, ...]], measured: dict[str, Any]
    ) -> None:
        """Apply one operation's effect: remove, move, then add relations."""
        for tpl in rule.remove:
            self.relations = [r for r in self.relations if not self._matches(r, tpl, binds)]
        if "follow" in rule.move:
            self._follow(binds[rule.move["follow"][1:]], binds[rule.move["object"][1:]])
        if "place" in rule.move:
            point = measured.get(rule.move["measured"])
            on = rule.move["on"][1:]
            binds = {**binds, on: self._place(binds[rule.move["place"][1:]], binds[on], point)}
        for tpl in rule.add:
            if tpl.when is not None:
                count = len(binds[tpl.when[1][1:]])
                if (tpl.when[0] == "single") != (count == 1):
                    continue
            self.relations.extend(self._instances(tpl, binds))

    def _names(self, text: str, binds: dict[str, tuple[str, ...]]) -> tuple[str, ...] | None:
        """Names a template term stands for; None for the wildcard."""
        if text == "*":
            return None
        return binds[text[1:].rstrip("*")]

    def _matches(self, r: Relation, tpl: Template, binds) -> bool:
        if r.type != tpl.type:
            return False
        subj = self._names(tpl.subject, binds)
        if subj is not None and r.subject not in subj:
            return False
        obj = self._names(tpl.object, binds)
        if obj is None:
            return True
        return (r.obj in obj) if isinstance(r.obj, str) else set(r.obj) == set(obj)

    def _instances(self, tpl: Template, binds) -> list[Relation]:
        subjects = self._names(tpl.subject, binds) or ()
        if not tpl.subject.endswith("*"):
            subjects = subjects[:1]
        objs = self._names(tpl.object, binds) or ()
        if not objs:
            return []
        obj: str | tuple[str, ...] = objs[0] if len(objs) == 1 else tuple(objs)
        out = []
        for subject in subjects:
            at = wrt = None
            if tpl.wrt is not None:
                ref = self._names(tpl.wrt, binds) or ()
                if len(ref) == 1:
                    wrt = ref[0]
                    p, q = self.nodes[subject].position, self.nodes[wrt].position
                    at = _sub(p, q) if p is not None and q is not None else None
            out.append(Relation(tpl.type, subject, obj, at, wrt if at is not None else None))
        return out

    def _follow(self, hands: tuple[str, ...], objects: tuple[str, ...]) -> None:
        """The objects (and what rests on them) move with the hand from now on."""
        hand = self.nodes[hands[0]] if hands else None
        for name in objects:
            for moving in (name, *self.supported_by(name)):
                pos = self.nodes[moving].position
                if hand is not None and hand.position is not None and pos is not None:
                    self.followers[moving] = _sub(pos, hand.position)

    def _clear_of_neighbours(self, node: EnvNode, at: Vec3, ignore: set[str]) -> Vec3:
        """``at`` moved out of any block it overlaps sideways by a measurement error."""
        if node.size is None:
            return at
        clearance = float(self.rules.constants["place-clearance"])
        limit = float(self.rules.constants["place-overlap-limit"])
        pos = list(at)
        for other in self.nodes.values():
            if other.name in ignore or other.name == node.name or other.kind != node.kind:
                continue
            if other.position is None or other.size is None or other.name in self.followers:
                continue
            pen = [(node.size[i] + other.size[i]) / 2 - abs(pos[i] - other.position[i])
                   for i in range(3)]
            if min(pen) <= 0:
                continue  # apart along some axis
            axis = 0 if pen[0] <= pen[1] else 1
            if pen[axis] > limit:
                continue  # not a measurement error: leave it for the physics to show
            away = 1.0 if pos[axis] >= other.position[axis] else -1.0
            pos[axis] += away * (pen[axis] + clearance)
        return (pos[0], pos[1], pos[2])

    def _place(self, objects, supports, point: Vec3 | None) -> tuple[str, ...]:
        """Put the object at the measured point, its height from the supports' tops.

        Returns the supports it rests on there: the objects whose top face carries its
        bottom face under its footprint where it was let go (Sec. V-B4). The ones found
        on the way down (the hand still beside the spot) may be fewer or others.
        """
        tops = [self.nodes[s].top() for s in supports if s in self.nodes]
        for name in objects:
            node = self.nodes[name]
            riders = [r for r in self.followers if r != name]
            for moving in (name, *riders):
                self.followers.pop(moving, None)
            old = node.position or (0.0, 0.0, 0.0)
            x, y = (point[0], point[1]) if point is not None else (old[0], old[1])
            height = node.size[2] if node.size else 0.0
            z = (max(tops) if tops else 0.0) + height / 2.0
            node.position = self._clear_of_neighbours(node, (float(x), float(y), float(z)),
                                                      set(supports) | set(riders))
            delta = _sub(node.position, old)
            for rider in riders:
                p = self.nodes[rider].position
                if p is not None:
                    self.nodes[rider].position = _add(p, delta)
            if tops and all(self.nodes[s].kind == node.kind for s in supports if s in self.nodes):
                below = self._carrying(node, set(riders))
                if below:
                    supports = tuple(below)
        return tuple(supports)

    def _carrying(self, node: EnvNode, riders: set[str]) -> list[str]:
        """Objects whose top face is at ``node``'s bottom (within 10 mm, as for located
        objects) and under its footprint by more than the support overlap."""
        if node.position is None or node.size is None:
            return []
        bottom = node.position[2] - node.size[2] / 2.0
        out = []
        for other in self.objects():
            if other is node or other.name in riders or other.position is None:
                continue
            if other.size is None or abs(other.top() - bottom) > 10.0:
                continue
            if all((node.size[i] + other.size[i]) / 2.0 - abs(node.position[i] - other.position[i])
                   > SUPPORT_OVERLAP_MM for i in range(2)):
                out.append(other.name)
        return out
