"""A family scenario from its structures: where they stand, the two initial layouts, the steps.

Structures (``Piece``) are set on free table spots; every other object lies
loose, clear of them by the classic generator's margins (room for the
fingers), or starts stacked on another (``Piece.starts_on``, and for the
stacked-start family stacks drawn here). A stack's top is always picked
before its base, so no pick carries an unplanned rider. The text is
design.md's scenario format; ``perception.world.generator.generate`` loads it
to validate it (the symbolic replay of perception.world.layout).
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass

import numpy as np

from perception.world.generator.classic import (
    CATALOGUE,
    DISTRACTORS,
    LEVELS,
    MAX_HEIGHT,
    Crowded,
    _interleave,
    _num,
    clear,
    footprint,
    free_spot,
)
from perception.world.generator.families import FAMILY_BUILDERS
from perception.world.generator.pieces import Piece, Size
from perception.world.scenario import Noise

FIT = 20.0  # mm a stack's top may overhang its base's footprint in total, per axis
BLOCKED_GOAL = 0.15  # share of drafts with an execution object lying on a goal spot
TOUCHING = 0.15  # share of drafts with two execution objects in side contact
GRIP_MM = 120.0  # the widest side a touching pair's blocks may be gripped across
TOUCH_PLACED = 0.15  # share of drafts with an empty-hand touch of a block already placed
ROWED = 0.5  # share of layouts whose small blocks lying alone start in a close row
SMALL_MM = 20.0  # ... blocks no wider than this, ROW_GAPS mm apart
ROW_GAPS = (6, 12)
INSET_MM = 5.0  # a deck's ends reach this far past the piers it starts on


@dataclass
class Draft:
    """A drawn family scenario before it is written out."""

    family: str
    pieces: list[Piece]
    shapes: dict[str, Size]  # shape -> size
    objects: dict[str, str]  # object -> shape (teach names)
    teach: dict[str, tuple]  # object -> (x, y) | base object
    execute: dict[str, tuple]
    distract: dict[str, str]
    steps: list[dict]
    touches: int
    blocker: str | None = None  # an execution object set on a goal spot (``_block_a_goal``)
    touching: tuple[str, str] | None = None  # an execution object set against another


def draw(rng: np.random.Generator, family: str) -> Draft:
    """One attempt at a scenario of ``family`` (Crowded or ValueError: draw again)."""
    builders, turnable = FAMILY_BUILDERS[family]
    pieces, taken = [], []
    for i in range(int(rng.choice([1, 1, 2]))):
        along_x = turnable and bool(rng.random() < 0.5)
        p = builders[int(rng.integers(len(builders)))](rng, "ab"[i], along_x)
        if along_x:
            p.transpose()
        x0, x1, y0, y1 = p.footprint()
        cx, cy, fp = free_spot(rng, (x1 - x0, y1 - y0), taken)
        p.shift(cx - (x0 + x1) / 2, cy - (y0 + y1) / 2)
        taken.append(fp)
        pieces.append(p)
    shapes: dict[str, Size] = {}
    for p in pieces:
        for s, size in p.shapes.items():
            if shapes.setdefault(s, size) != size:
                raise Crowded()  # two pieces drew one shape name with two sizes
    distract = {f"other{k}": str(rng.choice(DISTRACTORS))
                for k in range(1, int(rng.choice([0, 0, 1])) + 1)}
    shapes.update({s: CATALOGUE[s] for s in distract.values()})
    objects = {n: s for p in pieces for n, s in p.objects.items()} | distract
    achieves = [p.achieves for p in pieces]
    order = _interleave(rng, achieves) if rng.random() < 0.5 else [a for x in achieves for a in x]
    picked = [a["obj"] for a in order]
    fixed = {t: b for p in pieces for t, b in p.starts_on.items()}
    layouts = []
    stay = {n: p.where[n] for p in pieces for n in p.stays if n not in fixed}
    for _ in range(2):  # teach, execute
        stacks = dict(fixed)
        if family == "stacked-start":
            _add_stacks(rng, stacks, picked, objects, shapes)
        # what stands in the structure from the start is there when taught, anywhere after
        layouts.append(_layout(rng, objects, shapes, stacks, taken,
                               {} if layouts else stay))
    steps, touches = _steps(rng, order, layouts[0])
    # drawn from a generator of its own, seeded by the draft: every other draw (and so
    # every scenario the bench drew before this) stays as it was
    own = np.random.default_rng(zlib.crc32(repr((sorted(layouts[1].items()), steps)).encode()))
    blocker = _block_a_goal(own, layouts[1], objects, shapes, taken) \
        if own.random() < BLOCKED_GOAL else None
    touching = _touch_a_neighbour(own, layouts[1], objects, shapes, taken) \
        if own.random() < TOUCHING else None
    later = np.random.default_rng(zlib.crc32(repr(("touch", steps)).encode()))
    if touches < 2 and later.random() < TOUCH_PLACED:
        touches += _touch_a_placed(later, steps)
    for lay in layouts:  # each from a generator of its own, as above
        rowing = np.random.default_rng(zlib.crc32(repr(("row", sorted(lay.items()))).encode()))
        if rowing.random() < ROWED:
            _row_up_small(rowing, lay, objects, shapes, taken)
    return Draft(family, pieces, shapes, objects, layouts[0], layouts[1], distract, steps,
                 touches, blocker, touching)


def _alone(layout: dict) -> list[str]:
    """Objects lying on the table with nothing on them, sorted by name."""
    return sorted(n for n, w in layout.items() if len(w) == 2
                  and not any(len(v) == 1 and n in (v[0] if isinstance(v[0], tuple) else v)
                              for v in layout.values()))


def _footprints(layout: dict, objects: dict, shapes: dict, but: set[str]) -> list[tuple]:
    """Footprints of the objects on the table, but ``but``."""
    return [footprint(w[0], w[1], shapes[objects[n]][0], shapes[objects[n]][1])
            for n, w in layout.items() if len(w) == 2 and n not in but]


def _block_a_goal(rng: np.random.Generator, layout: dict, objects: dict, shapes: dict,
                  taken: list) -> str | None:
    """Move one execution object lying alone on the table to the middle of where a
    structure is built (helper round 5, t15 and t29: a plate lying where its legs go, a
    disk on the goal spot): the robot must set it aside first. Nothing moves when the
    spot would meet another object. Returns the object moved, if one was."""
    alone = _alone(layout)
    if not alone or not taken:
        return None
    name = alone[int(rng.integers(len(alone)))]
    x0, x1, y0, y1 = taken[int(rng.integers(len(taken)))]
    cx, cy = round((x0 + x1) / 2), round((y0 + y1) / 2)
    size = shapes[objects[name]]
    if not clear(footprint(cx, cy, size[0], size[1]),
                 _footprints(layout, objects, shapes, {name})):
        return None
    layout[name] = (float(cx), float(cy))
    return name


def _touch_a_neighbour(rng: np.random.Generator, layout: dict, objects: dict, shapes: dict,
                       taken: list) -> tuple[str, str] | None:
    """Move one execution object lying alone on the table into side contact with another,
    along x or y (helper round 9, w42-w100: a 24 x 36 block touching a cube along x). The
    robot must grip it across its free side, its watch must name the block it took, and
    a repair must turn the wrist from where it is. Nothing moves when the new spot is not
    clear of the rest, or a block could be gripped across neither side. Returns the
    object moved and the one it touches, if one was moved."""
    alone = _alone(layout)
    if len(alone) < 2:
        return None
    i, j = (int(k) for k in rng.choice(len(alone), 2, replace=False))
    a, b = alone[i], alone[j]
    sa, sb = shapes[objects[a]], shapes[objects[b]]
    axis, side = int(rng.integers(2)), float(rng.choice([-1.0, 1.0]))
    if max(sa[1 - axis], sb[1 - axis]) > GRIP_MM:
        return None
    at = [float(layout[b][0]), float(layout[b][1])]
    at[axis] += side * (sa[axis] + sb[axis]) / 2
    slide = int(min(sa[1 - axis], sb[1 - axis]) // 4)
    at[1 - axis] += float(rng.integers(-slide, slide + 1))
    if not clear(footprint(at[0], at[1], sa[0], sa[1]),
                 _footprints(layout, objects, shapes, {a, b}) + list(taken)):
        return None
    layout[a] = (at[0], at[1])
    return a, b


def _row_up_small(rng: np.random.Generator, layout: dict, objects: dict, shapes: dict,
                  taken: list) -> list[str]:
    """Line up two to four small blocks lying alone (at most SMALL_MM wide) in a row along
    x or y, ROW_GAPS mm apart, on a free spot (helper round 20: 15 mm cubes 10 mm apart
    along x; the approach began 16 mm beside a cube, nearer its neighbour, and the
    neighbour was named). Nothing moves when no spot is free. Returns the blocks moved."""
    small = [n for n in _alone(layout) if max(shapes[objects[n]][:2]) <= SMALL_MM]
    if len(small) < 2:
        return []
    names = [small[int(i)] for i in rng.permutation(len(small))[:int(rng.integers(2, 5))]]
    axis = int(rng.integers(2))
    sizes = [shapes[objects[n]] for n in names]
    gaps = [int(rng.integers(ROW_GAPS[0], ROW_GAPS[1] + 1)) for _ in names[1:]]
    length = sum(z[axis] for z in sizes) + sum(gaps)
    width = max(z[1 - axis] for z in sizes)
    try:
        cx, cy, _ = free_spot(rng, (length, width) if axis == 0 else (width, length),
                              _footprints(layout, objects, shapes, set(names)) + list(taken))
    except Crowded:
        return []
    at = (cx, cy)[axis] - length / 2
    for name, size, gap in zip(names, sizes, [*gaps, 0], strict=True):
        spot = [cx, cy]
        spot[axis] = at + size[axis] / 2
        layout[name] = (float(spot[0]), float(spot[1]))
        at += size[axis] + gap
    return names


def _add_stacks(rng: np.random.Generator, stacks: dict, picked: list[str], objects: dict,
                shapes: dict) -> None:
    """One or two stacks: a top picked before its base (or resting on a distractor). One
    draft in three grows a stack a block or two higher (helper round 6, e08: a slab and
    three cubes, whose top cube near the table's corners hid the stack from the finder)."""
    def high(n: str) -> float:
        """The height of the stack whose bottom block is ``n``."""
        return shapes[objects[n]][2] + sum(high(t) for t, b in stacks.items() if b == n)

    def bottom(n: str) -> str:
        return bottom(stacks[n]) if n in stacks else n

    def fits(top: str, base: str) -> bool:
        t, b = shapes[objects[top]], shapes[objects[base]]
        return t[0] <= b[0] + FIT and t[1] <= b[1] + FIT and \
            t[2] + high(bottom(base)) <= MAX_HEIGHT

    later = {n: picked.index(n) if n in picked else len(picked) for n in objects}
    pairs = [(t, b) for t in picked for b in objects if later[t] < later[b] and fits(t, b)]
    for _ in range(int(rng.integers(1, 3))):
        pairs = [(t, b) for t, b in pairs if not ({t, b} & (set(stacks) | set(stacks.values())))]
        if not pairs:
            return
        t, b = pairs[int(rng.integers(len(pairs)))]
        stacks[t] = b
    # drawn from a generator of its own: the drafts whose stacks do not grow stay as they were
    own = np.random.default_rng(zlib.crc32(repr(sorted(stacks.items())).encode()))
    while stacks and own.random() < 1 / 3:
        tops = [n for n in stacks if n not in stacks.values()]
        grow = [(t, b) for t in picked for b in tops if later[t] < later[b] and fits(t, b)
                and t not in set(stacks) | set(stacks.values())]
        if not grow:
            return
        t, b = grow[int(own.integers(len(grow)))]
        stacks[t] = b


def _layout(rng: np.random.Generator, objects: dict, shapes: dict, stacks: dict,
            taken: list, stay: dict | None = None) -> dict[str, tuple]:
    """Initial positions: (x, y) on the table, or (base,) for a stack's top (base a name,
    or two for a top across two blocks: they stand under its ends, INSET_MM in); ``stay``:
    objects standing at given spots of the structures' sites (``Piece.stays``)."""
    out: dict[str, tuple] = dict(stay or {})
    busy = list(taken)
    for top, base in stacks.items():
        if isinstance(base, tuple):  # a deck across two piers: one footprint
            dx, dy = shapes[objects[top]][:2]
            ends = [shapes[objects[b]] for b in base]
            size = [dx, max(dy, *(e[1] for e in ends))]
            x, y, fp = free_spot(rng, size, busy)
            busy.append(fp)
            for side, b, e in zip((-1, 1), base, ends, strict=True):
                out[b] = (x + side * (dx / 2 - e[0] / 2 - INSET_MM), y)
    for name in objects:
        if name in stacks or name in out:
            continue
        chain, n = [name], name
        while n in stacks.values():  # everything standing on it, for its footprint
            n = next(t for t, b in stacks.items() if b == n)
            chain.append(n)
        size = [max(shapes[objects[c]][i] for c in chain) for i in (0, 1)]
        x, y, fp = free_spot(rng, size, busy)
        busy.append(fp)
        out[name] = (x, y)
    for top, base in stacks.items():
        out[top] = (base,)
    return out


def _steps(rng: np.random.Generator, order: list[dict], teach: dict) -> tuple[list[dict], int]:
    """pick/place steps, with up to two touches: of objects lying alone on the table, or
    of a place's single support by the block about to be put on it."""
    stacked = {n for n, w in teach.items() if len(w) == 1} | \
        {b for w in teach.values() if len(w) == 1
         for b in (w[0] if isinstance(w[0], tuple) else (w[0],))}
    supports = {s for a in order for s in ([a["on"]] if isinstance(a["on"], str) else a["on"])}
    steps, touches, moved = [], 0, set()
    for a in order:
        free = sorted(n for n in teach if n not in moved | stacked | supports and n != a["obj"])
        if touches < 2 and free and rng.random() < 0.2:
            steps.append({"touch": str(rng.choice(free))})
            touches += 1
        steps.append({"pick": a["obj"]})
        if touches < 2 and isinstance(a["on"], str) and a["on"] != "table" and "at" not in a \
                and "align" not in a and rng.random() < 0.15:
            # touch the support with the block in hand first, where the place then puts
            # it (its centre: the same hand path, so as feasible as the place itself)
            steps.append({"touch": a["on"]})
            touches += 1
        steps.append({"place": a["obj"], **{k: v for k, v in a.items() if k != "obj"}})
        moved.add(a["obj"])
    return steps, touches


def _touch_a_placed(rng: np.random.Generator, steps: list[dict]) -> int:
    """Insert, before a pick, an empty-hand touch of a block placed earlier with nothing on
    it yet (helper round 20, g3003: a pillar of a 2 x 2 grid touched before the plate
    went on; judged late, it read as picked). Returns the touches added (0 or 1)."""
    placed, covered, spots = [], set(), []
    for i, step in enumerate(steps):
        if "pick" in step and i > 0 and "touch" not in steps[i - 1]:
            spots += [(i, n) for n in placed if n not in covered and n != step["pick"]]
        if "place" in step:
            placed.append(step["place"])
            covered |= {step["on"]} if isinstance(step["on"], str) else set(step["on"])
    if not spots:
        return 0
    i, name = spots[int(rng.integers(len(spots)))]
    steps.insert(i, {"touch": name})
    return 1


def _names(on: str | list[str], prefix: str = "") -> str:
    """``on`` as YAML: a name or a flow list of names."""
    return prefix + on if isinstance(on, str) else f"[{', '.join(prefix + n for n in on)}]"


def _objects(layout: dict, objects: dict, prefix: str) -> list[str]:
    """The lines of one workspace's objects."""
    lines = []
    for n, w in layout.items():
        where = f"on: {_names(list(w[0]) if isinstance(w[0], tuple) else w[0], prefix)}" \
            if len(w) == 1 else f"at: [{_num(w[0])}, {_num(w[1])}]"
        lines.append(f"    {prefix}{n}: {{shape: {objects[n]}, {where}}}")
    return lines


def to_yaml(d: Draft, seed: int, level: str) -> str:
    """The scenario file text (design.md format)."""
    k, base = LEVELS[level], Noise()
    lines = [f"# Generated by perception.world.generator (seed {seed}, noise {level}), "
             f"family {d.family}: {', '.join(p.kind for p in d.pieces)};",
             f"# {len(d.distract)} irrelevant object(s)" + (
                 f"; x-{d.blocker} lies on a goal spot" if d.blocker else "") + (
                 f"; x-{d.touching[0]} is set against x-{d.touching[1]}" if d.touching
                 else "") + ".",
             f"name: gen-{seed}-{level}", f"seed: {seed}", "shapes:"]
    lines += [f"  {s}: [{', '.join(_num(v) for v in size)}]"
              for s, size in sorted(d.shapes.items())]
    lines += ["noise:", f"  pixel: {base.pixel * k:g}", f"  tremor: {base.tremor * k:g}",
              f"  speed: [{base.speed[0]:g}, {base.speed[1]:g}]", "teach:", "  objects:"]
    lines += _objects(d.teach, d.objects, "")
    lines.append("  demonstration:")
    for step in d.steps:
        kind = next(iter(step))
        lines.append(f"    - {kind}: {step[kind]}")
        if kind != "place":
            continue
        lines.append(f"      on: {_names(step['on'])}")
        if "at" in step:
            lines.append(f"      at: [{_num(step['at'][0])}, {_num(step['at'][1])}]")
        if "align" in step:
            lines.append(f"      align: {{with: {step['align'][0]}, face: {step['align'][1]}}}")
    lines += ["execute:", "  objects:"] + _objects(d.execute, d.objects, "x-")
    return "\n".join(lines) + "\n"
