"""The execution-phase environment model (Sec. VII-A): expected state while tracing a plan.

It starts as the taught model with positions replaced by measurements
(matching), keeps the irrelevant measured objects as obstacles, and is updated
with each operation's expected effect: the hand's position after every
primitive (a held object and whatever rests on it move along), and the
relation changes SC⁻ / SC⁺ of each operator when it completes. Monitoring can
compare it with what the cameras see after each operation.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from lbw_engine.do.plan import Relation
from lbw_engine.model.geometry import TABLE, Vec, support_relations

RelKey = tuple[str, str, tuple[str, ...]]  # (type, subject, sorted objects)


@dataclass
class Body:
    """One object of the model: shape, size and expected centre (mm)."""

    shape: str
    size: Vec
    position: Vec
    relevant: bool = True  # False for measured objects the plan does not use


@dataclass
class ExecModel:
    """Objects, relations, the hand and what it holds."""

    bodies: dict[str, Body]
    support_types: tuple[str, ...]  # (single, multiple) support relation names
    hand: Vec
    held: str | None = None
    relations: set[RelKey] = field(default_factory=set)
    grip_offsets: dict[str, float] = field(default_factory=dict)  # see jaws.py

    @classmethod
    def from_measurements(
        cls,
        bodies: Mapping[str, Body],
        support_types: tuple[str, ...],
        hand: Vec,
    ) -> ExecModel:
        """A model whose support relations are read from the measured geometry."""
        model = cls(dict(bodies), tuple(support_types), tuple(hand))
        boxes = {n: (b.position, b.size) for n, b in model.bodies.items()}
        single, multiple = support_types[0], support_types[-1]
        for name, (rtype, objs) in support_relations(boxes, single, multiple).items():
            model.relations.add((rtype, name, objs))
        return model

    def support_of(self, name: str) -> RelKey | None:
        """The support relation of ``name`` (an object rests on one thing or several)."""
        for rel in self.relations:
            if rel[1] == name and rel[0] in self.support_types:
                return rel
        return None

    def riders(self, name: str) -> list[str]:
        """Objects resting, directly or through others, on ``name`` (they ride along)."""
        out: list[str] = []
        frontier = [name]
        while frontier:
            base = frontier.pop()
            for rel in sorted(self.relations):
                if rel[0] in self.support_types and base in rel[2] and rel[1] not in out:
                    if rel[1] != name:
                        out.append(rel[1])
                        frontier.append(rel[1])
        return out

    def move_hand(self, p: Vec) -> None:
        """The hand goes to ``p``; a held object and its riders move by the same amount."""
        delta = tuple(p[k] - self.hand[k] for k in range(3))
        if self.held is not None:
            for name in [self.held, *self.riders(self.held)]:
                b = self.bodies[name]
                b.position = tuple(b.position[k] + delta[k] for k in range(3))
        self.hand = tuple(p)

    def grasp(self, reach: float = 15.0) -> str | None:
        """Close the hand: it holds the object between its jaws.

        That is an object whose footprint holds the hand's x-y and whose height
        range, extended ``reach`` mm upward (the fingers hang below the grip
        centre), holds the hand's z; the closest centre wins.
        """
        hx, hy, hz = self.hand
        best, best_d = None, float("inf")
        for name, b in self.bodies.items():
            (x, y, z), (sx, sy, sz) = b.position, b.size
            if abs(hx - x) <= sx / 2 and abs(hy - y) <= sy / 2 and \
                    z - sz / 2 <= hz <= z + sz / 2 + reach and abs(hz - z) < best_d:
                best, best_d = name, abs(hz - z)
        self.held = best
        return best

    def release(self) -> None:
        """Open the hand."""
        self.held = None

    def apply(self, sc_minus: Iterable[Relation], sc_plus: Iterable[Relation]) -> None:
        """An operator's relation changes: SC⁻ removed, SC⁺ added (Sec. VII-A 2c)."""
        for r in sc_minus:
            self.relations.discard((r.type, r.subject, tuple(sorted(r.objects))))
        for r in sc_plus:
            if r.type in self.support_types:
                old = self.support_of(r.subject)
                if old is not None:
                    self.relations.discard(old)
            self.relations.add((r.type, r.subject, tuple(sorted(r.objects))))

    def final_supports(self, names: Iterable[str]) -> dict[str, tuple[str, tuple[str, ...]]]:
        """Expected support relation of each named object (among these and the table)."""
        keep = set(names) | {TABLE}
        out = {}
        for n in names:
            rel = self.support_of(n)
            if rel is not None and set(rel[2]) <= keep:
                out[n] = (rel[0], tuple(sorted(rel[2])))
        return out

    def settled(self, names: Iterable[str]) -> dict[str, Vec]:
        """Expected resting centres: x, y as traced, z from the tops of the supports.

        A placed object is released a little above its support; after settling
        it rests on it, which is what verification measures.
        """
        memo: dict[str, float] = {}

        def centre_z(name: str, depth: int) -> float:
            if name not in memo:
                b = self.bodies[name]
                rel = self.support_of(name)
                under = [s for s in rel[2] if s == TABLE or s in self.bodies] if rel else []
                if not under or depth > len(self.bodies):
                    memo[name] = b.position[2]
                else:
                    tops = [0.0 if s == TABLE else
                            centre_z(s, depth + 1) + self.bodies[s].size[2] / 2 for s in under]
                    memo[name] = max(tops) + b.size[2] / 2
            return memo[name]

        return {n: (self.bodies[n].position[0], self.bodies[n].position[1], centre_z(n, 0))
                for n in names}
