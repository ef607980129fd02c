"""Symbolic block layouts: where boxes rest, replayed step by step without physics.

The scenario loader uses this to reject impossible demonstrations (a box off
the table, overlapping another, a place on an object the hand carries ...);
the demonstrator uses the resolved positions as the hand's targets; ground
truth reads the support relations after every step. The physical world must
agree with it (tests/world checks that).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from lbw_engine.model.geometry import TABLE_X, TABLE_Y
from lbw_engine.names import HAND
from lbw_engine.rules import Roles

MAX_TOP = 300.0  # structures stay below this height
EPS = 0.01  # mm: boxes touching face to face do not overlap
HEIGHT_TOL = 0.5  # mm: supports of one box must have tops this close

Vec3 = tuple[float, float, float]


def box_bounds(center: Sequence[float], size: Sequence[float]) -> tuple[tuple[float, float], ...]:
    """(lo, hi) along x, y, z of an axis-aligned box."""
    return tuple((c - s / 2, c + s / 2) for c, s in zip(center, size, strict=True))


def overlaps(a: tuple, b: tuple, axes: Iterable[int] = (0, 1, 2)) -> bool:
    """Do two boxes' bounds overlap by more than EPS along every given axis?"""
    return all(min(a[i][1], b[i][1]) - max(a[i][0], b[i][0]) > EPS for i in axes)


@dataclass
class Layout:
    """Centres, sizes and support relations of the boxes of one workspace."""

    center: dict[str, Vec3]
    size: dict[str, Vec3]
    support: dict[str, tuple[str, ...]]  # name -> ("table",) | supports; held: ()
    held: str | None = None

    @classmethod
    def build(cls, specs: dict[str, dict]) -> Layout:
        """Resolve ``{name: {size, on, at}}`` into resting centres (ValueError(msg, name))."""
        lay = cls({}, {k: tuple(v["size"]) for k, v in specs.items()}, {})
        visiting: set[str] = set()

        def resolve(name: str) -> None:
            """Place ``name`` after its supports."""
            if name in lay.center:
                return
            if name in visiting:
                raise ValueError("the 'on' relations form a cycle", name)
            visiting.add(name)
            spec = specs[name]
            for s in spec["on"]:
                if s != "table":
                    resolve(s)
            lay.center[name] = lay.rest_center(name, spec["on"], spec["at"])
            lay.support[name] = tuple(spec["on"])
            lay.check_box(name, lay.center[name], skip={name})
            visiting.discard(name)

        for name in specs:
            resolve(name)
        lay.check_loads()
        return lay

    @classmethod
    def from_objects(cls, objects: Iterable[Any]) -> Layout:
        """A layout from ObjectSpec records."""
        objs = list(objects)
        return cls(
            {o.name: tuple(o.center) for o in objs},
            {o.name: tuple(o.size) for o in objs},
            {o.name: tuple(o.on) for o in objs},
        )

    def copy(self) -> Layout:
        """An independent copy."""
        return replace(self, center=dict(self.center), size=dict(self.size),
                       support=dict(self.support))

    def bounds(self, name: str, center: Vec3 | None = None) -> tuple:
        """Bounds of ``name`` (optionally at another centre)."""
        return box_bounds(center or self.center[name], self.size[name])

    def rest_center(self, name: str, on: Sequence[str], at: Sequence[float] | None) -> Vec3:
        """Centre of ``name`` resting on the table or on the given supports."""
        h = self.size[name][2]
        if tuple(on) == ("table",):
            return (float(at[0]), float(at[1]), h / 2)
        tops = {s: self.center[s][2] + self.size[s][2] / 2 for s in on}
        lo, hi = min(tops.values()), max(tops.values())
        if hi - lo > HEIGHT_TOL:
            detail = ", ".join(f"{s} at {z:g} mm" for s, z in tops.items())
            raise ValueError(f"the supports' tops differ in height ({detail})", name)
        if at is None:
            at = [sum(self.center[s][i] for s in on) / len(on) for i in (0, 1)]
        return (float(at[0]), float(at[1]), hi + h / 2)

    def check_box(self, name: str, center: Vec3, skip: set[str]) -> None:
        """Table bounds, height limit, resting on its supports, no overlap (ValueError)."""
        (x0, x1), (y0, y1), (z0, z1) = b = self.bounds(name, center)
        if x0 < TABLE_X[0] - EPS or x1 > TABLE_X[1] + EPS or y0 < TABLE_Y[0] - EPS \
                or y1 > TABLE_Y[1] + EPS:
            raise ValueError(
                f"'{name}' at x {center[0]:g}, y {center[1]:g} reaches off the table "
                f"(x {x0:g}..{x1:g}, y {y0:g}..{y1:g}; the table spans x -300..300, y 0..400)",
                name)
        if z1 > MAX_TOP + EPS:
            raise ValueError(f"'{name}' reaches {z1:g} mm, above the {MAX_TOP:g} mm limit", name)
        held_up = [s for s in self.support.get(name, ()) or () if s != "table"]
        for s in held_up:
            if not overlaps(b, self.bounds(s), (0, 1)):
                raise ValueError(f"'{name}' does not rest on '{s}' (their footprints are apart)",
                                 name)
        if held_up and not all(
                min(self.bounds(s)[k][0] for s in held_up) - EPS <= center[k]
                <= max(self.bounds(s)[k][1] for s in held_up) + EPS for k in (0, 1)):
            # its centre beyond its supports: the block falls off (helper round 11, v108a)
            raise ValueError(f"'{name}' would tip off {', '.join(repr(s) for s in held_up)}: "
                             f"its centre (x {center[0]:g}, y {center[1]:g}) is not over them",
                             name)
        for other in self.center:
            if other not in skip and other != self.held and overlaps(b, self.bounds(other)):
                raise ValueError(f"'{name}' would overlap '{other}'", name)

    def riders(self, name: str) -> list[str]:
        """Objects resting on ``name``, directly or through others (they ride along)."""
        out: list[str] = []
        frontier = [name]
        while frontier:
            base = frontier.pop()
            for other, sup in self.support.items():
                if base in sup and other not in out and other != name:
                    out.append(other)
                    frontier.append(other)
        return out

    def carried(self, name: str) -> list[str]:
        """Objects whose whole weight ``name`` bears: resting on it, or on it and on others
        it bears, directly or through them (a beam across two towers is neither tower's)."""
        out: list[str] = []
        grown = True
        while grown:
            grown = False
            for other, sup in self.support.items():
                if other != name and other not in out and sup and \
                        all(s == name or s in out for s in sup):
                    out.append(other)
                    grown = True
        return out

    def centre_of_mass(self, names: Sequence[str]) -> tuple[float, float]:
        """x and y of the centre of mass of ``names`` (uniform density)."""
        mass = [math.prod(self.size[n]) for n in names]
        return tuple(sum(m * self.center[n][k] for m, n in zip(mass, names, strict=True))
                     / sum(mass) for k in (0, 1))

    def check_loads(self) -> None:
        """Each block, with what it carries, balances on its supports (ValueError)."""
        for name, on in self.support.items():
            held_up = [s for s in on or () if s != "table"]
            load = [name, *self.carried(name)] if held_up else []
            if len(load) < 2:
                continue  # check_box did the block alone
            com = self.centre_of_mass(load)
            if not all(min(self.bounds(s)[k][0] for s in held_up) - EPS <= com[k]
                       <= max(self.bounds(s)[k][1] for s in held_up) + EPS for k in (0, 1)):
                raise ValueError(
                    f"'{name}' would tip off {', '.join(repr(s) for s in held_up)} under "
                    f"what rests on it: their centre of mass (x {com[0]:.0f}, y {com[1]:.0f}) "
                    "is not over them", name)

    def relations(self, roles: Roles) -> list[list]:
        """Support and holding relations in the actions.json form, named by the rules' roles
        (rules/effects.yaml: hold, support single / multiple)."""
        rels: list[list] = []
        for name in sorted(self.center):
            sup = self.support.get(name, ())
            if name == self.held:
                rels.append([roles.hold, HAND, name])
            elif len(sup) == 1:
                rels.append([roles.single, name, sup[0]])
            elif sup:
                rels.append([roles.multiple, name, sorted(sup)])
        return rels


def _move(lay: Layout, name: str, riders: list[str], new_center: Vec3) -> None:
    """Move ``name`` and the boxes riding on it by the same offset."""
    d = [n - o for n, o in zip(new_center, lay.center[name], strict=True)]
    for r in [name, *riders]:
        lay.center[r] = tuple(c + dc for c, dc in zip(lay.center[r], d, strict=True))


def _aligned(lay: Layout, name: str, dest: Vec3, with_: str, face: str) -> Vec3:
    """Centre after sliding ``name`` along ``with_`` until their ``face`` faces are coplanar."""
    size, wc, ws = lay.size[name], lay.center[with_], lay.size[with_]
    flush = 1 if face in ("north", "south") else 0  # axis made coplanar
    contact = 1 - flush  # the boxes touch across the other horizontal axis
    sign = 1 if face in ("north", "east") else -1
    out = list(dest)
    out[flush] = wc[flush] + sign * (ws[flush] - size[flush]) / 2
    side = 1 if dest[contact] >= wc[contact] else -1
    out[contact] = wc[contact] + side * (ws[contact] + size[contact]) / 2
    return tuple(out)


def replay(lay: Layout, steps: Sequence[Any]) -> tuple[tuple, tuple[Layout, ...]]:
    """Resolve each step's destination; ValueError(message, step index, key) if impossible."""
    resolved, states = [], []
    for i, step in enumerate(steps):
        if step.kind == "pick":
            if lay.held is not None:
                raise ValueError(f"cannot pick '{step.obj}' while holding '{lay.held}'", i,
                                 "pick")
            carrier = _carrier(lay, step.obj)
            if carrier:
                raise ValueError(f"'{step.obj}' is carried by the hand", i, "pick")
            lay.held = step.obj
            lay.support[step.obj] = ()
            resolved.append(step)
        elif step.kind == "touch":
            if lay.held == step.obj or _carrier(lay, step.obj):
                raise ValueError(f"cannot touch '{step.obj}': it is in the hand", i, "touch")
            resolved.append(step)
        else:
            resolved.append(_place(lay, step, i))
        states.append(lay.copy())
    return tuple(resolved), tuple(states)


def _carrier(lay: Layout, name: str) -> bool:
    """Is ``name`` carried by the hand (held, or riding on the held box)?"""
    return lay.held is not None and (name == lay.held or name in lay.riders(lay.held))


def _place(lay: Layout, step: Any, i: int) -> Any:
    """Resolve one place step (and its align slide) in ``lay``."""
    if lay.held != step.obj:
        holds = f"'{lay.held}'" if lay.held else "nothing"
        raise ValueError(f"cannot place '{step.obj}': the hand holds {holds}", i, "place")
    riders = lay.riders(step.obj)
    for s in step.on:
        if s in riders:
            raise ValueError(f"cannot place on '{s}': it rides on '{step.obj}'", i, "on")
    try:
        dest = lay.rest_center(step.obj, step.on, step.at)
    except ValueError as exc:
        raise ValueError(exc.args[0], i, "on") from None
    lay.support[step.obj] = tuple(step.on)
    final = dest
    moving = {step.obj, *riders}
    if step.align is not None:
        w = step.align.with_
        if w in moving:
            raise ValueError(f"cannot align with '{w}': it moves with '{step.obj}'", i, "align")
        final = _aligned(lay, step.obj, dest, w, step.align.face)
        wb, fb = lay.bounds(w), lay.bounds(step.obj, final)
        if not overlaps(wb, fb, (2,)):
            raise ValueError(f"'{step.obj}' and '{w}' are not at the same height", i, "align")
    lay.held = None
    for center, key in ((dest, "at" if step.at else "on"), (final, "align")):
        _move(lay, step.obj, riders, center)
        try:
            for r in [step.obj, *riders]:
                lay.check_box(r, lay.center[r], skip=moving)
            lay.check_loads()
        except ValueError as exc:
            raise ValueError(exc.args[0], i, key if step.align or key != "align" else "on") \
                from None
    return replace(step, dest=dest, final=final)


def slide_mm(step: Any) -> float | None:
    """How far (x, y; mm) a demonstration step's align slides its block from where it is
    set down; None for a step without an align."""
    if step.align is None or step.dest is None or step.final is None:
        return None
    return math.dist(step.dest[:2], step.final[:2])


def slides(step: Any, least: float) -> bool:
    """Whether a demonstration step aligns its block by sliding it at least ``least`` mm
    (x, y) from where it was set down: a shorter one is a place already in line."""
    mm = slide_mm(step)
    return mm is not None and mm >= least


def slide_reading(step: Any, least: float, doubt: float) -> tuple[bool, bool]:
    """(must, may): whether the eye must read a demonstration step's align as a slide, and
    whether it may. A slide within ``doubt`` mm of ``least`` may be read either way (rules
    ``align-slide-doubt``): must = at least ``least + doubt``, may = at least
    ``least - doubt``; with no doubt both are ``slides(step, least)``."""
    mm = slide_mm(step)
    if mm is None:
        return False, False
    return mm >= least + doubt, mm >= least - doubt
