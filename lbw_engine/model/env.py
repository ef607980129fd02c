"""The environment model (Sec. IV-A): ENV-nodes, their positions and relations.

Nodes are of the ENV classes of Fig. 8: one World, one HandLoc (``hand``),
one Table (``table``) and one Loc per object. Relations are
(type, subject, object[, at, wrt]) records; ``at`` is the subject's position
relative to the ``wrt`` node (Fig. 14, Fig. 21). Operation effects come from
rules/effects.yaml as relation templates (``lbw_engine.model.effects``). Execution
traces its expected state in the same model (Sec. VII-A).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from lbw_engine.model.geometry import Box, Vec, resting_on
from lbw_engine.names import HAND, TABLE, WORLD
from lbw_engine.rules import RuleSet

TABLE_SIZE: Vec3 = (600.0, 400.0, 0.0)  # design.md workspace; the top face is z = 0


@dataclass
class EnvNode:
    """An ENV-node: a named region of the workspace (Table II slots we use)."""

    name: str
    kind: str  # "World" | "HandLoc" | "Table" | "Loc"
    position: Vec3 | None = None
    size: Vec3 | None = None
    shape: str | None = None
    relevant: bool = True  # execution: False for measured objects the plan does not use

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

    @property
    def objects(self) -> tuple[str, ...]:
        """The relation's object(s) as a tuple."""
        return self.obj if isinstance(self.obj, tuple) else (self.obj,)

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


Vec3 = Vec


def _vec(p: Iterable[float]) -> Vec3:
    """A plain float triple."""
    x, y, z = (float(c) for c in p)
    return (x, y, z)


def _sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@dataclass(frozen=True)
class Body:
    """A measured object for an execution model: shape, size, centre (mm), whether the
    plan uses it."""

    shape: str
    size: Vec3
    position: Vec3
    relevant: bool = True


@dataclass
class EnvModel:
    """The ENV-nodes of one workspace and the relations among them."""

    rules: RuleSet
    nodes: dict[str, EnvNode] = field(default_factory=dict)
    relations: list[Relation] = field(default_factory=list)
    followers: dict[str, Vec3] = field(default_factory=dict)  # name -> offset from the hand
    # Execution (do/jaws.py): how each object is gripped — the jaw axis (0: x, 1: y)
    # and the grip point's offset along the object across the jaws — and the wrist's
    # turn now (degrees from world x, design.md "Robot").
    grips: dict[str, tuple[int, float]] = field(default_factory=dict)
    wrist: float = 0.0
    placed: set[str] = field(default_factory=set)  # objects the traced plan has put down

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

    def holding(self) -> str | None:
        """The one object the hand holds, if any."""
        held = self.held()
        return held[0] if held else None

    @property
    def hand(self) -> Vec3:
        """Where the hand is."""
        return self.nodes[HAND].position or (0.0, 0.0, 0.0)

    @property
    def bodies(self) -> dict[str, EnvNode]:
        """The objects by name (execution's view of the Loc nodes)."""
        return {n.name: n for n in self.objects()}

    def support_of(self, name: str) -> Relation | None:
        """The support relation of ``name`` (an object rests on one thing or several)."""
        return next((r for r in self.relations
                     if r.subject == name and r.type in self.rules.support_relations), None)

    def supports_of(self, name: str) -> list[str]:
        """What ``name`` rests on, by the support relations of the rules."""
        out: list[str] = []
        for r in self.relations:
            if r.type in self.rules.support_relations and r.subject == name:
                out.extend(r.objects)
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
    def locate(self, objects: Iterable[tuple[str, str, Vec3, Vec3]]) -> None:
        """Register located objects (name, shape, size, centre) and what each rests on."""
        for name, shape, size, pos in objects:
            self.nodes[name] = EnvNode(name, "Loc", _vec(pos), _vec(size), shape)
        self.initial_relations()

    def move_node(self, name: str, pos: Vec3) -> None:
        """Set a node's position; objects following the hand come along."""
        self.nodes[name].position = pos
        if name == HAND:
            for follower, offset in self.followers.items():
                self.nodes[follower].position = _add(pos, offset)

    def follow(self, objects: Iterable[str]) -> None:
        """The objects, and what rests on them, move with the hand from now on (Fig. 8)."""
        hand = self.nodes[HAND].position
        for name in objects:
            for moving in (name, *self.supported_by(name)):
                pos = self.nodes[moving].position
                if hand is not None and pos is not None:
                    self.followers[moving] = _sub(pos, hand)

    def boxes(self, names: Iterable[str] | None = None) -> dict[str, Box]:
        """(centre, size) of the located objects (or of ``names``) that have both."""
        nodes = self.objects() if names is None else self.get(names)
        return {n.name: (n.position, n.size) for n in nodes
                if n.position is not None and n.size is not None}

    def initial_relations(self) -> None:
        """Each located object rests on what geometry says is under it (geometry.resting_on),
        else on the table: the support relations of the rules' roles, with :at :wrt."""
        boxes = self.boxes()
        for node in self.objects():
            if any(r.subject == node.name for r in self.relations) or node.name not in boxes:
                continue
            below = resting_on(node.name, boxes) or [TABLE]
            if len(below) == 1:
                rtype, obj, ref = self.rules.roles.single, below[0], below[0]
            else:
                rtype, obj, ref = self.rules.roles.multiple, tuple(below), TABLE
            wrt = self.nodes[ref]
            at = _sub(node.position, wrt.position) if wrt.position else node.position
            self.relations.append(Relation(rtype, node.name, obj, at, ref))

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

    # --- execution: the expected state while a plan is traced (Sec. VII-A) ------
    def __deepcopy__(self, memo: dict) -> EnvModel:
        """A copy to try things on (the rules are shared, not copied)."""
        env = EnvModel(self.rules, {n: replace(v) for n, v in self.nodes.items()},
                       list(self.relations), dict(self.followers), dict(self.grips), self.wrist,
                       set(self.placed))
        memo[id(self)] = env
        return env

    @classmethod
    def measured(cls, rules: RuleSet, bodies: dict[str, Body], hand: Vec3) -> EnvModel:
        """A model of measured objects whose support relations are read from the geometry."""
        env = cls(rules)
        env.nodes[HAND].position = _vec(hand)
        for name, node in bodies.items():
            env.nodes[name] = EnvNode(name, "Loc", _vec(node.position), _vec(node.size),
                                      node.shape, node.relevant)
        env.initial_relations()
        return env

    def move_hand(self, p: Vec3) -> None:
        """The hand goes to ``p``; a held object and its riders come along."""
        self.move_node(HAND, _vec(p))

    def grasp(self, above: float = 15.0) -> str | None:
        """Close the hand: it holds the object between its jaws (and its riders follow).

        That is an object whose footprint holds the hand's x-y (less the offset of
        the grip planned for it, ``grips``: a finger may grip a small block off its
        centre, away from a neighbour) and whose height range, extended ``above`` mm
        upward (the fingers hang below the grip centre), holds the hand's z; the
        closest centre wins.
        """
        best, best_d = None, float("inf")
        for node in self.objects():
            (x, y, z), (sx, sy, sz) = node.position, node.size
            hand = list(self.hand)
            axis, offset = self.grips.get(node.name, (0, 0.0))
            hand[1 - axis] -= offset
            hx, hy, hz = hand
            if abs(hx - x) <= sx / 2 and abs(hy - y) <= sy / 2 and \
                    z - sz / 2 <= hz <= z + sz / 2 + above and abs(hz - z) < best_d:
                best, best_d = node.name, abs(hz - z)
        if best is not None:
            self.hold(best)
        return best

    def shove(self, name: str, delta: Vec3) -> None:
        """``name`` and what rests on it are pushed by ``delta`` (the fine motion's push)."""
        for moving in (name, *self.supported_by(name)):
            self.nodes[moving].position = _add(self.nodes[moving].position, delta)

    def hang(self, name: str, pos: Sequence[float]) -> None:
        """Held ``name`` (and what rests on it) is at ``pos`` now, and keeps that offset from
        the hand: a detector measured where the block hangs once taken up (actions.json's
        positions; before, a block taken stayed at its table spot in the model)."""
        self.shove(name, _sub(_vec(pos), self.nodes[name].position))
        self.follow([name])

    def hold(self, name: str) -> None:
        """The hand holds ``name``; it and what rests on it follow the hand."""
        self.relations.append(Relation(self.rules.hold_relation, HAND, name))
        self.follow([name])

    def release(self) -> None:
        """Open the hand: nothing is held, nothing follows it."""
        self.relations = [r for r in self.relations
                          if not (r.type == self.rules.hold_relation and r.subject == HAND)]
        self.followers.clear()

    def apply(self, sc_minus: Iterable[Any], sc_plus: Iterable[Any]) -> None:
        """A plan operator's relation changes (plan relations: type, subject, objects):
        SC⁻ removed, SC⁺ added; a new support relation replaces the old one (Sec. VII-A 2c)."""
        for r in sc_minus:
            self.relations = [x for x in self.relations if not (
                x.type == r.type and x.subject == r.subject and set(x.objects) == set(r.objects))]
        for r in sc_plus:
            if r.type in self.rules.support_relations:
                self.relations = [x for x in self.relations if not (
                    x.subject == r.subject and x.type in self.rules.support_relations)]
                self.placed.add(r.subject)
            obj = tuple(sorted(r.objects)) if len(r.objects) > 1 else r.objects[0]
            self.relations.append(Relation(r.type, r.subject, obj))

    def final_supports(self, names: Iterable[str]) -> dict[str, tuple[str, tuple[str, ...]]]:
        """Expected support relation of each named object (among these and the table)."""
        keep = set(names) | {TABLE}
        out = {}
        for n in names:
            rel = self.support_of(n)
            if rel is not None and set(rel.objects) <= keep:
                out[n] = (rel.type, tuple(sorted(rel.objects)))
        return out

    def settled(self, names: Iterable[str]) -> dict[str, Vec3]:
        """Expected resting centres: x, y as traced, z from the tops of the supports.

        A placed object is released a little above its support; after settling
        it rests on it, which is what verification measures.
        """
        memo: dict[str, float] = {}
        bodies = self.bodies

        def centre_z(name: str, depth: int) -> float:
            if name not in memo:
                b = bodies[name]
                rel = self.support_of(name)
                under = [s for s in rel.objects if s == TABLE or s in bodies] if rel else []
                if not under or depth > len(bodies):
                    memo[name] = b.position[2]
                else:
                    tops = [0.0 if s == TABLE else
                            centre_z(s, depth + 1) + bodies[s].size[2] / 2 for s in under]
                    memo[name] = max(tops) + b.size[2] / 2
            return memo[name]

        return {n: (bodies[n].position[0], bodies[n].position[1], centre_z(n, 0))
                for n in names}
