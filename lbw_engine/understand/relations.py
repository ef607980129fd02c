"""Relations as set elements: equality with `:at` coordinates under a tolerance.

A relation is ``[type, subject, object(s)]`` optionally followed by
``{"at": [x, y, z], "wrt": name}`` (design.md, Fig. 14, Fig. 21). The state
algebra of Sec. VI-B needs set difference and intersection over relations taken
from different snapshots, where a position measured twice differs by noise.

Decision (docs/analysis.md, "Relation equality"): two relations are equal when
type, subject, the *set* of objects and `wrt` are equal and their `at` vectors
differ by at most ``tolerance`` mm on every axis (or both have no `at`). Because
`at` is relative to `wrt` (the support), the bricks resting on the plank of
Fig. 14 keep the same relation when the plank is carried: it stays in SI.

Tolerance is not transitive, so sets cannot hash raw values. A ``RelationTable``
interns every relation it reads: the first relation seen for a key becomes the
canonical one, and later ones within tolerance map to that same object. After
interning, relations compare by identity, which keeps the set algebra exact and
fast, and the output shows the first measured value.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any


class Rel:
    """One interned relation; compare by identity (the table guarantees uniqueness)."""

    __slots__ = ("type", "subject", "objects", "multiple", "at", "wrt", "has_meta")

    def __init__(
        self,
        type_: str,
        subject: str,
        objects: tuple[str, ...],
        multiple: bool,
        at: tuple[float, ...] | None,
        wrt: str | None,
        has_meta: bool,
    ) -> None:
        self.type = type_
        self.subject = subject
        self.objects = objects
        self.multiple = multiple
        self.at = at
        self.wrt = wrt
        self.has_meta = has_meta

    def names(self) -> tuple[str, ...]:
        """The objects a relation talks about: its subject and object(s) (not `wrt`)."""
        return (self.subject, *self.objects)

    def to_json(self) -> list[Any]:
        """The design.md form ``[type, subject, object(s), {"at", "wrt"}?]``."""
        obj: Any = list(self.objects) if self.multiple else self.objects[0]
        out: list[Any] = [self.type, self.subject, obj]
        if self.has_meta:
            meta: dict[str, Any] = {}
            if self.at is not None:
                meta["at"] = list(self.at)
            if self.wrt is not None:
                meta["wrt"] = self.wrt
            out.append(meta)
        return out

    def __repr__(self) -> str:
        """Readable form for test failures."""
        return f"Rel{self.to_json()!r}"


def sort_key(rel: Rel) -> tuple:
    """A deterministic output order: by type, subject, objects, then position."""
    return (rel.type, rel.subject, rel.objects, rel.wrt or "", rel.at or ())


def sorted_json(rels: Iterable[Rel]) -> list[list[Any]]:
    """Relations as JSON lists in a stable order."""
    return [r.to_json() for r in sorted(rels, key=sort_key)]


class RelationTable:
    """Interns relations so that equal-within-tolerance relations are one object."""

    def __init__(self, tolerance: float) -> None:
        self.tolerance = tolerance
        self._by_key: dict[tuple, list[Rel]] = {}

    def intern(
        self,
        type_: str,
        subject: str,
        obj: str | list[str],
        at: list[float] | tuple[float, ...] | None = None,
        wrt: str | None = None,
        has_meta: bool | None = None,
    ) -> Rel:
        """The canonical relation equal to the given one (created on first sight)."""
        multiple = isinstance(obj, (list, tuple))
        objects = tuple(obj) if multiple else (obj,)
        # An on-multiple's supports are a set: their listed order does not matter.
        key = (type_, subject, frozenset(objects) if multiple else objects, multiple, wrt)
        at_t = tuple(at) if at is not None else None
        bucket = self._by_key.setdefault(key, [])
        for rel in bucket:
            if _same_position(rel.at, at_t, self.tolerance):
                return rel
        if has_meta is None:
            has_meta = at is not None or wrt is not None
        rel = Rel(type_, subject, objects, multiple, at_t, wrt, has_meta)
        bucket.append(rel)
        return rel

    def from_json(self, raw: list[Any]) -> Rel:
        """Intern a relation already checked to have the design.md shape."""
        meta = raw[3] if len(raw) > 3 else None
        if meta is None:
            return self.intern(raw[0], raw[1], raw[2])
        return self.intern(raw[0], raw[1], raw[2], meta.get("at"), meta.get("wrt"), True)


def _same_position(
    a: tuple[float, ...] | None, b: tuple[float, ...] | None, tolerance: float
) -> bool:
    """Both absent, or every coordinate within ``tolerance`` (Chebyshev distance)."""
    if a is None or b is None:
        return a is None and b is None
    return len(a) == len(b) and all(abs(x - y) <= tolerance for x, y in zip(a, b, strict=True))
