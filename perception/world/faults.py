"""Faults while the robot works (design.md ``execute.faults``; Sec. IX-C, failure treatment).

Three kinds, each tied to the N-th ACHIEVE the robot executes (1-based):

* ``{during: N, kind: drop}`` — the gripper lets go halfway through that
  ACHIEVE's transfer (its jaws slacken by SLIP_MM; the robot is not told).
  "Halfway" is read from the world: the robot's moves follow a minimum-jerk
  profile whose speed peaks at the middle of the move, so the block is dropped
  when its horizontal speed, while held, has passed its peak;
* ``{after: N, kind: displace, object: NAME, by: [dx, dy]}`` — an outside agent
  slides the object; what rests on it may fall;
* ``{after: N, kind: remove, object: NAME}`` — the object is taken away.

The injector lives on the world side: the pipeline tells it where the robot is
in its plan (an outside agent that acts between the robot's operators), but the
robot and the monitor are never told what it did — they must see it.
This module also reads and checks ``execute.faults`` (strict, file:line errors).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from lbw_engine.guard import number, shorten
from lbw_engine.model.geometry import TABLE_X, TABLE_Y
from lbw_engine.yamlio import line_of

KINDS = ("drop", "displace", "remove")
_KEYS = {"drop": {"during", "kind"}, "displace": {"after", "kind", "object", "by"},
         "remove": {"after", "kind", "object"}}
WHEN_MAX = 10_000  # an ACHIEVE count no plan reaches; larger is a typo
BY_RANGE = (-600.0, 600.0)  # mm: the table is 600 mm wide
PEAK_MIN = 40.0  # mm/s: a held block slower than this is being lifted, not carried
# A drop is a slip: the jaws slacken by this much and the block falls out. Flung fully
# open (the 150 mm of the robot's gripper) the fingers came down around the place spot
# as wide as that and toppled a pillar standing 80 mm beside it (a user's table).
SLIP_MM = 10.0


@dataclass(frozen=True)
class Fault:
    """One fault: its kind, the ACHIEVE it is tied to, and (displace/remove) its object."""

    kind: str
    when: int  # ``during`` for drop, ``after`` for displace and remove
    obj: str | None = None
    by: tuple[float, float] = (0.0, 0.0)
    line: int | None = None


def parse_faults(cx: Any, raw: Any, parent: Any, objects: dict) -> tuple[Fault, ...]:
    """``execute.faults``: a list of fault mappings naming ``execute.objects`` objects.

    ``cx`` is the scenario loader's error context (``fail``, ``place``).
    """
    where = "execute.faults"
    if not isinstance(raw, list):
        raise cx.fail("must be a list of faults ({during: N, kind: drop}, ...)", parent,
                      "faults", where)
    out = []
    for i, item in enumerate(raw):
        w = f"{where}[{i}]"
        if not isinstance(item, dict) or "kind" not in item:
            raise cx.fail("a fault must be a mapping with 'kind' (drop, displace, remove)",
                          raw, i, w)
        kind = item["kind"]
        if kind not in KINDS:
            raise cx.fail(f"unknown fault kind {shorten(kind)} (kinds: {', '.join(KINDS)})",
                          item, "kind", f"{w}.kind")
        allowed = _KEYS[kind]
        for key in item:
            if key not in allowed:
                raise cx.fail(f"unknown key '{key}' for a {kind} fault (expected: "
                              f"{', '.join(sorted(allowed))})", item, key, f"{w}.{key}")
        for key in sorted(allowed):
            if key not in item:
                raise cx.fail(f"a {kind} fault needs '{key}'", raw, i, f"{w}.{key}")
        when_key = "during" if kind == "drop" else "after"
        when = item[when_key]
        if isinstance(when, bool) or not isinstance(when, int) or not 1 <= when <= WHEN_MAX:
            raise cx.fail(f"must be an ACHIEVE count from 1 to {WHEN_MAX}, got {shorten(when)}",
                          item, when_key, f"{w}.{when_key}")
        obj = item.get("object")
        if obj is not None and (not isinstance(obj, str) or obj not in objects):
            raise cx.fail(f"unknown object {shorten(obj)} (not in execute.objects)", item,
                          "object", f"{w}.object")
        by = (0.0, 0.0)
        if "by" in item:
            raw_by = item["by"]
            if not isinstance(raw_by, list) or len(raw_by) != 2:
                raise cx.fail(f"expected a list of 2 numbers, got {shorten(raw_by)}", item,
                              "by", f"{w}.by")
            by = tuple(number(d, cx.place(raw_by, k, f"{w}.by[{k}]"), *BY_RANGE, unit="mm")
                       for k, d in enumerate(raw_by))
        out.append(Fault(kind, when, obj, by, line_of(raw, i)))
    return tuple(out)


class FaultInjector:
    """Applies a scenario's faults to a World as the robot works; records what it did."""

    def __init__(self, world: Any, faults: tuple[Fault, ...], names: dict[str, str]) -> None:
        """``names`` maps an ``execute.objects`` name to its world body (the same today)."""
        self.world = world
        self.faults = list(faults)
        self.names = names
        self.achieve = 0  # the ACHIEVE under way (1-based), 0 before the first
        self.injected: list[dict] = []
        self._applied: set[int] = set()  # indices into ``faults``
        self._peak = 0.0
        self._last: tuple[float, float, float] | None = None  # time, x, y of the gripper
        self._armed: Fault | None = None
        self._dropped: list[tuple[dict, str]] = []  # drop records and their bodies, in flight

    def begin(self, n: int) -> None:
        """The robot starts its ``n``-th ACHIEVE: arm a drop tied to it."""
        self.achieve = n
        self._peak, self._last = 0.0, None
        self._armed = next((f for f in self.faults if f.kind == "drop" and f.when == n), None)

    def end(self, n: int) -> None:
        """The robot finished its ``n``-th ACHIEVE: displace or remove objects tied to it."""
        self._armed = None
        for rec, body in self._dropped:  # landed by now: on the table, or past its edge
            if body in self.world.names and _off_table(self.world.positions()[body]):
                rec["off_table"] = True
        self._dropped = []
        for f in self.faults:
            if f.when != n or f.kind == "drop":
                continue
            body = self.names.get(f.obj or "")
            if body is None or body not in self.world.names:
                continue  # already removed
            if f.kind == "displace":
                before = self.world.positions()[body]
                self.world.displace(body, f.by)
                after = self.world.positions()[body]
                # Slid past the table's edge, the object is as good as removed.
                self._record(f, off_table=_off_table(after))
                # how far it went: along y a block stops at the first it meets (a cube
                # wedged in a pyramid's row moved 3 mm of a 9 mm nudge: fault bench 7000)
                self.injected[-1]["moved_mm"] = round(math.dist(before[:2], after[:2]), 1)
            else:
                self.world.remove_block(body)
                self._record(f)

    def on_step(self, world: Any) -> None:
        """Per world step: let go of the held block once its carry speed has peaked."""
        f = self._armed
        if f is None:
            return
        for g in world.grippers:
            if g.kind != "arm" or g.holding is None:
                continue
            # the carry's speed over the table, along x and y: the simulation's bodies move
            # in x-z, the gripper carries them along y itself (a carry along y never made
            # the body's x speed peak, and the drop never fired: helper round 8, v42, v61)
            x, y, _ = g.position
            last, self._last = self._last, (world.time, x, y)
            if last is None or world.time <= last[0]:
                continue
            speed = math.hypot(x - last[1], y - last[2]) / (world.time - last[0])
            self._peak = max(self._peak, speed)
            if self._peak >= PEAK_MIN and speed < 0.9 * self._peak:  # past the middle
                body = g.holding
                g.open(g.opening + SLIP_MM)
                self._armed = None
                self._record(f)
                self._dropped.append((self.injected[-1], body))

    def missed(self) -> list[dict]:
        """The scenario's faults that never fired (their ACHIEVE never ran, or their object
        was gone), as written: a user must not believe a fault was tried when it was not."""
        out = []
        for i, f in enumerate(self.faults):
            if i not in self._applied:
                when = "during" if f.kind == "drop" else "after"
                out.append({"kind": f.kind, when: f.when, **({"object": f.obj} if f.obj else {}),
                            **({"line": f.line} if f.line is not None else {})})
        return out

    def _record(self, f: Fault, off_table: bool = False) -> None:
        """Note an injected fault (evaluation only: the robot never reads it)."""
        self._applied.add(next(i for i, g in enumerate(self.faults) if g is f))
        rec: dict[str, Any] = {"kind": f.kind, "achieve": self.achieve,
                               "t": round(self.world.time, 2)}
        if f.obj:
            rec["object"] = f.obj
        if off_table:
            rec["off_table"] = True
        self.injected.append(rec)


def _off_table(position: Any) -> bool:
    """Whether a body's centre lies past the table's edge (or has fallen below it): for the
    robot the object is as good as removed (a dropped brick thrown off the table, fault
    seed 9005)."""
    x, y, z = position
    return not (TABLE_X[0] <= x <= TABLE_X[1] and TABLE_Y[0] <= y <= TABLE_Y[1]) or z < 0.0
