"""Structures of the scenario families, built at the origin, then turned and moved into place.

A ``Piece`` is one structure: the shapes it uses, its objects, the ACHIEVE steps
that build it (each an ``obj`` put ``on`` the table or on objects, optionally
``at`` a point and ``align``-ed with a neighbour, as in design.md's scenario
format) and the footprint it covers when built. Builders in
``perception.world.generator.families`` draw a piece along y; ``transpose``
turns it so its rows run along x (x and y swapped, shapes renamed where their
footprint is not square, align faces swapped with them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

Size = tuple[float, float, float]
Rect = tuple[float, float, float, float]  # x0, x1, y0, y1

# transposing x <-> y maps the +y face onto the +x face, and -y onto -x
_FACE_SWAP = {"north": "east", "east": "north", "south": "west", "west": "south"}


def rect(cx: float, cy: float, sx: float, sy: float) -> Rect:
    """Footprint of a box of size sx x sy centred at cx, cy."""
    return (cx - sx / 2, cx + sx / 2, cy - sy / 2, cy + sy / 2)


def union(rects: list[Rect]) -> Rect:
    """The smallest rectangle holding all of ``rects``."""
    return (min(r[0] for r in rects), max(r[1] for r in rects),
            min(r[2] for r in rects), max(r[3] for r in rects))


def aligned_xy(xy: tuple[float, float], size: Size, w_xy: tuple[float, float],
               w_size: Size, face: str) -> tuple[float, float]:
    """Where an align slide ends (the rule of perception.world.layout's replay, in x, y):
    ``face`` faces coplanar, the boxes touching across the other horizontal axis."""
    flush = 1 if face in ("north", "south") else 0
    contact = 1 - flush
    sign = 1 if face in ("north", "east") else -1
    out = list(xy)
    out[flush] = w_xy[flush] + sign * (w_size[flush] - size[flush]) / 2
    side = 1 if xy[contact] >= w_xy[contact] else -1
    out[contact] = w_xy[contact] + side * (w_size[contact] + size[contact]) / 2
    return out[0], out[1]


@dataclass
class Piece:
    """One structure of a family scenario (coordinates in mm on the table top)."""

    kind: str
    shapes: dict[str, Size] = field(default_factory=dict)  # shape name -> size
    objects: dict[str, str] = field(default_factory=dict)  # object -> shape
    achieves: list[dict] = field(default_factory=list)  # {"obj", "on", "at"?, "align"?}
    where: dict[str, tuple[float, float]] = field(default_factory=dict)  # built x, y
    # initial stacks: top -> base, or -> (base, base) for a top across two side by side
    starts_on: dict[str, str | tuple[str, str]] = field(default_factory=dict)
    # objects that already stand where the structure is built when taught, never picked
    stays: set[str] = field(default_factory=set)

    def size(self, name: str) -> Size:
        """Box size of object ``name``."""
        return self.shapes[self.objects[name]]

    def add(self, name: str, shape: str, size: Size) -> None:
        """Declare an object (its shape must not change size within a scenario)."""
        if self.shapes.setdefault(shape, size) != size:
            raise ValueError(f"shape {shape!r} drawn with two sizes")
        self.objects[name] = shape

    def stand(self, name: str, xy: tuple[float, float], shape: tuple[str, Size],
              on: str | None = None) -> None:
        """``name`` stands at ``xy`` in the teach layout (on ``on``, which stands there)
        and is never picked: part of the structure from the start (helper round 17)."""
        self.add(name, *shape)
        self.where[name] = (float(xy[0]), float(xy[1]))
        self.stays.add(name)
        if on is not None:
            self.starts_on[name] = on

    def put(self, name: str, on: str | list[str], at: tuple[float, float] | None = None,
            align: tuple[str, str] | None = None, shape: tuple[str, Size] | None = None
            ) -> tuple[float, float]:
        """Record the ACHIEVE that puts ``name`` on ``on``; returns where it ends (x, y).

        Without ``at`` it lands on the centre of its supports (design.md's default);
        ``align`` = (with, face) slides it into side contact after setting it down.
        """
        if shape:
            self.add(name, *shape)
        step: dict = {"obj": name, "on": on}
        if at is not None:
            step["at"] = (float(at[0]), float(at[1]))
            xy = step["at"]
        else:
            sups = [on] if isinstance(on, str) else on
            xy = (sum(self.where[s][0] for s in sups) / len(sups),
                  sum(self.where[s][1] for s in sups) / len(sups))
        if align:
            step["align"] = align
            xy = aligned_xy(xy, self.size(name), self.where[align[0]], self.size(align[0]),
                            align[1])
        self.where[name] = xy
        self.achieves.append(step)
        return xy

    def footprint(self) -> Rect:
        """The table area the built structure covers."""
        return union([rect(*self.where[n], *self.size(n)[:2]) for n in self.where])

    def shift(self, dx: float, dy: float) -> None:
        """Move the whole structure by (dx, dy)."""
        self.where = {n: (x + dx, y + dy) for n, (x, y) in self.where.items()}
        for a in self.achieves:
            if "at" in a:
                a["at"] = (a["at"][0] + dx, a["at"][1] + dy)

    def transpose(self) -> None:
        """Swap x and y: a row along y now runs along x (shapes and faces follow)."""
        rename = {}
        for shape, (sx, sy, sz) in list(self.shapes.items()):
            if sx != sy:
                rename[shape] = f"{shape}-t"
                self.shapes[rename[shape]] = (sy, sx, sz)
                del self.shapes[shape]
        self.objects = {n: rename.get(s, s) for n, s in self.objects.items()}
        self.where = {n: (y, x) for n, (x, y) in self.where.items()}
        for a in self.achieves:
            if "at" in a:
                a["at"] = (a["at"][1], a["at"][0])
            if "align" in a:
                a["align"] = (a["align"][0], _FACE_SWAP[a["align"][1]])
