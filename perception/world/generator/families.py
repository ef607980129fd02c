"""The scenario families of issue #12: each class of layout the scenario format accepts.

Each family draws one or two structures (``Piece``) along y and turns about
half of them so their rows run along x. The families, and what each exercises:

| family         | what is built                                                           |
|----------------|-------------------------------------------------------------------------|
| axis           | rows, pyramids, arches, tables, along x or y (gaps 4-10 mm)             |
| gaps           | rows and 2x2 grids with 0-10 mm gaps on both axes; a block or a slab    |
|                | narrower than the cubes across a gap, a plate on the grid               |
| align          | a block set down near another and slid into side contact, any face      |
| small          | 10-20 mm cubes: towers, rows, one on a 40 mm cube; tapered towers       |
| pillars        | 12-18 mm wide, 110-120 mm tall pillars standing in a row                |
| beams          | a cross of two 180 mm beams, on the table or on two bricks              |
| bridge         | a plank across two towers (Fig. 18's multi-support place, lifted)       |
| three-supports | a plate on three bricks (a triangle or a line)                          |
| stairs         | a stack whose blocks are set off by 6-12 mm with ``at``                 |
| stacked-start  | classic structures whose parts start stacked, in teach and in execute  |
| rearrange      | the top of a stack taken off and put elsewhere; a loaded slat moved;    |
|                | a deck taken off two piers and one pier stood on it                     |
| twins          | a base moved with a rider as wide or wider across one side; a row of    |
|                | equal small blocks about a block apart                                  |

Sizes are integers drawn from the seed; every builder keeps structures under
MAX_HEIGHT (the robot's carrying height, rules/commands.yaml) and centres
loads over their supports, so the demonstration stands (tests/generator
simulates it).
"""

from __future__ import annotations

import zlib
from collections.abc import Callable

import numpy as np

from perception.world.generator.classic import CATALOGUE
from perception.world.generator.pieces import Piece

CUBE = CATALOGUE["cube"]
BRICK = CATALOGUE["brick"]


def _ri(rng: np.random.Generator, lo: int, hi: int) -> int:
    """An integer in [lo, hi]."""
    return int(rng.integers(lo, hi + 1))


def _row(p: Piece, rng: np.random.Generator, tag: str, n: int, shape: tuple[str, tuple],
         gaps: tuple[int, int], x: float = 0.0) -> list[str]:
    """``n`` boxes in a row along y at x, gaps drawn in ``gaps``, put down in random order
    (the caller may turn the row along x: the demonstrator's wrist turns to fit)."""
    size = shape[1]
    ys, y = [], 0.0
    for k in range(n):
        ys.append(y)
        y += size[1] + (_ri(rng, *gaps) if k < n - 1 else 0)
    mid = (ys[0] + ys[-1]) / 2
    names = [f"{tag}{k + 1}" for k in range(n)]
    for k in rng.permutation(n):
        p.put(names[k], "table", (x, ys[k] - mid), shape=shape)
    return names


def axis(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """A row, pyramid, arch or table; the caller turns half of them along x."""
    kind = str(rng.choice(["row", "pyramid", "arch", "table"]))
    p = Piece(f"{kind}")
    if kind == "row":
        _row(p, rng, f"{tag}-c", _ri(rng, 2, 4), ("cube", CUBE), (4, 10))
    elif kind == "pyramid":
        below = _row(p, rng, f"{tag}-c", _ri(rng, 2, 3), ("cube", CUBE), (4, 10))
        k = len(below)
        while len(below) > 1:
            above = []
            for j in rng.permutation(len(below) - 1):
                k += 1
                p.put(f"{tag}-c{k}", [below[j], below[j + 1]], shape=("cube", CUBE))
                above.append((j, f"{tag}-c{k}"))
            below = [n for _, n in sorted(above)]
    elif kind == "arch":
        d = _ri(rng, 30, 40) * 2
        legs = _row(p, rng, f"{tag}-pillar", 2, ("brick", BRICK), (d - 30, d - 30))
        p.put(f"{tag}-beam", legs, shape=("beam", (40, 130, 20)))
    else:
        _legs_and_top(p, rng, tag, [(-1, -1), (-1, 1), (1, 1), (1, -1)])
    return p


def _legs_and_top(p: Piece, rng: np.random.Generator, tag: str, corners: list) -> None:
    """Bricks at the given corners (signs of x, y) and a plate on all of them."""
    dx, dy = _ri(rng, 30, 36), _ri(rng, 40, 46)
    # one draw in seven per axis stands the legs under the plate's edges, 7 mm in (a plate
    # carried in over the near legs only was read as set on the table, docs/seeing.md)
    dx, dy = (58 if dx == 36 else dx), (68 if dy == 46 else dy)
    legs = []
    for k in rng.permutation(len(corners)):
        legs.append(f"{tag}-leg{k + 1}")
        p.put(legs[-1], "table", (corners[k][0] * dx, corners[k][1] * dy),
              shape=("brick", BRICK))
    p.put(f"{tag}-top", legs, shape=("plate", (100, 120, 10)))


def gaps(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """A row (maybe with a cube across one gap) or a 2x2 grid (maybe with a plate on it)."""
    if rng.random() < 0.5:
        p = Piece("gap-row")
        row = _row(p, rng, f"{tag}-c", _ri(rng, 2, 3), ("cube", CUBE), (0, 10))
        if rng.random() < 0.6:
            j = _ri(rng, 0, len(row) - 2)
            # A block wider than the cubes, or a slab narrower than them across the row:
            # its top face is then cut in two by the cubes' edges in the top view.
            across = ("block", CATALOGUE["block"]) if rng.random() < 0.5 else (
                "slab", (_ri(rng, 20, 32), _ri(rng, 60, 80), 20))
            p.put(f"{tag}-across", [row[j], row[j + 1]], shape=across)
        return p
    p = Piece("gap-grid")
    gx, gy = _ri(rng, 0, 10), _ri(rng, 0, 10)
    px, py = (CUBE[0] + gx) / 2, (CUBE[1] + gy) / 2
    cells = [(-px, -py), (-px, py), (px, py), (px, -py)]
    names = []
    for k in rng.permutation(4):
        names.append(f"{tag}-c{k + 1}")
        p.put(names[-1], "table", cells[k], shape=("cube", CUBE))
    if rng.random() < 0.5:
        p.put(f"{tag}-top", names, shape=("plate", (100, 120, 10)))
    return p


def align(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """One or two blocks set down 3-25 mm from a neighbour and slid flush on any face."""
    p = Piece("align")
    p.put(f"{tag}-base", "table", (0, 0), shape=("block", CATALOGUE["block"]))
    prev, prev_size = f"{tag}-base", CATALOGUE["block"]
    movers = [("cube", CUBE), ("brick", BRICK)]
    for k in range(_ri(rng, 1, 2)):
        shape = movers[int(rng.integers(len(movers)))]
        # any face: the demonstrator's fingers close across the side that stays free
        # (perception.world.wrist), so blocks may touch across x as well as y
        face = str(rng.choice(["north", "south", "east", "west"]))
        contact = 0 if face in ("north", "south") else 1  # the axis they touch across
        side = 1 if rng.random() < 0.5 else -1
        if k == 1 and (contact, side) == p.achieves[-1]["_side"]:
            side = -side  # the second block goes to the other side: never onto the first
        at = list(p.where[prev])
        # about one slide in nine is short (3-5 mm across, a quarter of the offset along):
        # within rules align-slide-doubt of align-slide, learned either way (docs/seeing.md)
        gap, along = _ri(rng, 8, 25), _ri(rng, -12, 12)
        if gap >= 23:
            gap, along = gap - 20, along / 4
        at[contact] += side * ((prev_size[contact] + shape[1][contact]) / 2 + gap)
        at[1 - contact] += along
        name = f"{tag}-b{k + 1}"
        p.put(name, "table", (at[0], at[1]), align=(f"{tag}-base", face), shape=shape)
        p.achieves[-1]["_side"] = (contact, side)
    for a in p.achieves:
        a.pop("_side", None)
    return p


def small(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """10-20 mm cubes: a tower, a row, one on a 40 mm cube, or a tapered tower of
    blocks 30, 20 and 10 mm wide and 12-16 mm tall (the tops of a support and of the
    block under it are no farther apart than a thin block: helper round 5, t09)."""
    s = _ri(rng, 10, 20)
    shape = ("small", (s, s, s))
    kind = str(rng.choice(["tower", "row", "on-cube", "tapered"]))
    p = Piece(f"small-{kind}")
    if kind == "tapered":
        below = "table"
        for k in range(_ri(rng, 2, 3)):
            side = 30 - 10 * k  # told apart by size: 10 mm on two axes
            p.put(f"{tag}-s{k + 1}", below, (0, 0) if below == "table" else None,
                  shape=(f"small{k + 1}", (side, side, _ri(rng, 12, 16))))
            below = f"{tag}-s{k + 1}"
    elif kind == "tower":
        below = "table"
        for k in range(_ri(rng, 2, 3)):
            p.put(f"{tag}-s{k + 1}", below, (0, 0) if below == "table" else None, shape=shape)
            below = f"{tag}-s{k + 1}"
    elif kind == "row":
        _row(p, rng, f"{tag}-s", _ri(rng, 2, 3), shape, (4, 10))
    else:
        p.put(f"{tag}-cube", "table", (0, 0), shape=("cube", CUBE))
        p.put(f"{tag}-s1", f"{tag}-cube", shape=shape)
    return p


def pillars(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """Two or three tall thin pillars standing in a row, 10-40 mm apart."""
    w, h = _ri(rng, 12, 18), _ri(rng, 110, 120)
    p = Piece("pillars")
    _row(p, rng, f"{tag}-p", _ri(rng, 2, 3), ("pillar", (w, w, h)), (10, 40))
    return p


def beams(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """A cross of two 180 mm beams, on the table or on two bricks."""
    p = Piece("cross")
    long_, cross = ("beam-long", (30, 180, 20)), ("beam-cross", (180, 30, 20))
    if rng.random() < 0.5:
        d = _ri(rng, 50, 70) * 2
        legs = _row(p, rng, f"{tag}-leg", 2, ("brick", BRICK), (d - 30, d - 30))
        p.put(f"{tag}-beam1", legs, shape=long_)
    else:
        p.put(f"{tag}-beam1", "table", (0, 0), shape=long_)
    p.put(f"{tag}-beam2", f"{tag}-beam1", shape=cross)
    return p


def bridge(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """Two towers of two cubes apart along y and a plank across them."""
    p = Piece("bridge")
    levels = 2  # two cubes each: the plank is lifted onto towers, at 80 mm
    d = _ri(rng, 50, 60) * 2
    # in three draws of eleven the first tower stands from the start and is never moved:
    # its bottom cube is in no operation (helper round 17, u199; no extra draw)
    standing = d % 10 == 0
    tops = []
    for t, y in enumerate((-d / 2, d / 2), 1):
        below = "table"
        for k in range(levels):
            name = f"{tag}-t{t}b{k + 1}"
            if standing and t == 1:
                p.stand(name, (0, y), ("cube", CUBE), None if below == "table" else below)
            else:
                p.put(name, below, (0, y) if below == "table" else None, shape=("cube", CUBE))
            below = name
        tops.append(below)
    p.put(f"{tag}-plank", tops, shape=("plank", (60, 160, 20)))
    return p


def three_supports(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """A plate on three bricks: a triangle or a line along y."""
    p = Piece("three-supports")
    if rng.random() < 0.5:
        _legs_and_top(p, rng, tag, [(-1, -1), (-1, 1), (1, 0)])
    else:
        legs = _row(p, rng, f"{tag}-leg", 3, ("brick", BRICK), (8, 14))
        p.put(f"{tag}-top", legs, shape=("plate", (100, 120, 10)))
    return p


def stairs(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """Two or three blocks stacked, each set off along y by 6-12 mm (``at``)."""
    p = Piece("stairs")
    step = _ri(rng, 6, 12) * (1 if rng.random() < 0.5 else -1)
    below, y = "table", 0.0
    for k in range(_ri(rng, 2, 3)):
        name = f"{tag}-s{k + 1}"
        p.put(name, below, (0, y), shape=("cube", CUBE))
        below, y = name, y + step
    return p


def rearrange(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """A stack of two or three; its top (then maybe the next) taken off and put elsewhere.
    Or a short plank with a small cube on its centre moved elsewhere, the cube riding
    along: the hand grips the plank just beside the cube, as near the cube's centre as
    the plank's (they coincide), and the search names the cube."""
    p = Piece("rearrange")
    draw = rng.random()
    # half the plank draws take a bridge apart instead, drawn from a generator of their
    # own: the other drafts stay as they were
    own = np.random.default_rng(zlib.crc32(f"{tag}{draw}".encode()))
    if draw < 1 / 3 and own.random() < 0.5:
        return _unbridge(p, own, tag)
    if draw < 1 / 3:
        plank, rider = f"{tag}-slat", f"{tag}-knob"
        p.add(plank, "slat", (_ri(rng, 100, 120), 30, 15))
        p.add(rider, "knob", (_ri(rng, 22, 28),) * 3)
        p.starts_on[rider] = plank
        p.put(plank, "table", (0, 0))
        return p
    if draw < 2 / 3:
        stack = [(f"{tag}-base", "cube", CUBE), (f"{tag}-top", "brick", BRICK)]
    else:  # 50 + 40 + 20 mm: under MAX_HEIGHT
        stack = [(f"{tag}-base", "block", CATALOGUE["block"]), (f"{tag}-mid", "cube", CUBE),
                 (f"{tag}-top", "tile", (30, 30, 20))]
    for name, *shape in stack:
        p.add(name, *shape)
    stack = [name for name, *_ in stack]
    for top, base in zip(stack[1:], stack, strict=False):
        p.starts_on[top] = base
    p.put(stack[-1], "table", (0, 0))
    if len(stack) == 3 and rng.random() < 0.5:
        p.put(stack[1], stack[-1])  # the middle one ends on the former top: the order reversed
    return p


def twins(rng: np.random.Generator, tag: str, along_x: bool) -> Piece:
    """Blocks that look alike where it matters: a base carried with a rider as wide as
    it (or wider) across one side, or a row of equal small blocks about a block apart.
    The jaws must close on the base, across the side the rider does not reach past
    (helper round 14, v48p, v48v, v48y); a hand coming down beside its target in the
    row is nearly as near the neighbour (round 14, AC: 20 mm cubes 40 mm apart)."""
    if rng.random() < 0.5:
        return _carry(Piece("carry"), rng, tag)
    s = _ri(rng, 10, 20)
    p = Piece("spaced-row")
    _row(p, rng, f"{tag}-s", _ri(rng, 2, 3), ("small", (s, s, s)), (max(s, 15), 30))
    return p


def _carry(p: Piece, rng: np.random.Generator, tag: str) -> Piece:
    """A base moved with its rider on it: an equal cube, or a 30 x 40 block under a
    40 x 30 one. Half the equal cubes have a column as tall as the two beside them, set
    down after: the stack then fits a listed shape (helper round 17, u97, u98); drawn
    from a generator of its own, so the other drafts stay as they were."""
    base, rider = f"{tag}-base", f"{tag}-rider"
    draw = rng.random()
    if draw < 0.5:
        p.add(base, "cube", CUBE)
        p.add(rider, "cube", CUBE)
        if np.random.default_rng(zlib.crc32(f"{tag}{draw}".encode())).random() < 0.5:
            p.add(f"{tag}-column", "column", (CUBE[0], CUBE[1], 2 * CUBE[2]))
            p.put(f"{tag}-column", "table", (0, CUBE[1] + 24))
    else:
        p.add(base, "post", (30, 40, _ri(rng, 30, 40)))
        p.add(rider, "lid", (40, 30, _ri(rng, 15, 20)))
    p.starts_on[rider] = base
    p.put(base, "table", (0, 0))
    return p


def _unbridge(p: Piece, rng: np.random.Generator, tag: str) -> Piece:
    """A deck that starts across two piers (in both layouts) is set down on the table, and
    one pier is stood on it: the piers are hidden under the deck from above, and the hand
    that takes the deck by its end is over a pier (helper round 11, 152 and 157)."""
    p.kind = "unbridge"
    deck, pier = f"{tag}-deck", f"{tag}-pier"
    p.add(deck, "deck", (_ri(rng, 140, 160), 40, 10))
    for k in (1, 2):
        p.add(f"{pier}{k}", "pier", (25, 25, 70))
    p.starts_on[deck] = (f"{pier}1", f"{pier}2")
    p.put(deck, "table", (0, 0))
    p.put(f"{pier}1", deck)
    return p


# Families whose draws are also simulated before they are kept: the demonstrator carries
# a pillar hanging ~90 mm below its hand and comes down ~160 mm above the table (its
# visual-search reach), so a pillar it brings over one standing can sweep it over;
# whether it does depends on where the hand comes from, which the replay cannot tell.
# Three stairs set off by 12 mm each hold their top two 18 mm off the lowest one's
# centre, 2 mm inside its edge: the hand's tremor at 4x sets them off a little more and
# the stack falls while it is demonstrated (bench seed 1065), so the script no longer
# says what happened. Cubes set down 0-10 mm apart (gaps) can land on a neighbour's edge
# under a tremulous hand and slide off: in bench seed 1151 (2x) a cube meant for 1 mm
# beside its neighbour came to rest 16 mm farther, and the next one, meant for 9 mm
# beside it, then overlapped it.
SIMULATED = frozenset({"pillars", "stairs", "gaps"})

Builder = Callable[[np.random.Generator, str, bool], Piece]

# family -> (builders it draws from, may it turn them along x?)
FAMILY_BUILDERS: dict[str, tuple[tuple[Builder, ...], bool]] = {
    "axis": ((axis,), True), "gaps": ((gaps,), True), "align": ((align,), False),
    "small": ((small,), True),
    "pillars": ((pillars,), True), "beams": ((beams,), True),
    "bridge": ((bridge,), True), "three-supports": ((three_supports,), True),
    "stairs": ((stairs,), True), "stacked-start": ((axis,), True),
    "rearrange": ((rearrange,), False), "twins": ((twins,), True),
}
