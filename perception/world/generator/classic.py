"""The classic family of seeded random scenarios (perception.world.generator).

``generate(seed, level)`` writes a scenario file (design.md format) with one to
three structures built side by side — towers, arches, tables (Fig. 18),
pyramids, inverted arches (Fig. 12-14) — sometimes interleaved ACHIEVE by
ACHIEVE, with touches (NO-OPs) of objects lying on the table and irrelevant
objects that are never moved. Hesitations come from the demonstrator itself
(``perception.world.demonstrator``: a pause before and after each local motion with
probability 0.5, drawn from the scenario's seed).

Everything is drawn from ``numpy.random.default_rng(seed)``; the noise level
only changes the ``noise`` block, so one seed gives the same task at every
level. Noise levels multiply the design defaults of pixel noise and hand
tremor (Sec. IX's "noisy images" and the human's unsteady hand); the
demonstrator's speed range stays at its default, which it is designed around
(approach speeds under Table IV's V_H).

Physical feasibility is by construction: shapes come from a fixed catalogue
whose sizes differ enough for the object-finder to tell them apart; every
multi-support place is centred over its supports; structures stay under
120 mm so the robot's approach height (rules/commands.yaml) clears them; every
box keeps room for the fingers on its x sides (the jaws close along x).
``load_text`` then replays the demonstration symbolically (perception.world.layout);
tests/generator also simulates it (perception.world) and checks the result is
the planned structure at rest.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from lbw_engine.model.geometry import TABLE_X, TABLE_Y
from perception.world.scenario import Noise, Scenario, load_text

# name -> (x, y, z) mm; pairwise at least 10 mm apart on two axes or 20 mm on one.
CATALOGUE: dict[str, tuple[int, int, int]] = {
    "brick": (30, 30, 50), "cube": (40, 40, 40), "block": (50, 50, 50), "beam": (130, 40, 20),
    "plate": (120, 100, 10), "plank": (160, 60, 20), "crate": (80, 60, 40), "disc": (50, 50, 20),
}
DISTRACTORS = ("crate", "disc")
LEVELS: dict[str, float] = {"nominal": 1.0, "2x": 2.0, "4x": 4.0}
MARGIN_X = 36.0  # mm free between boxes along x: a finger (10) + pre-shape clearance (12) + slack
MARGIN_Y = 24.0  # mm along y (fingers are 20 mm deep)
EDGE = 12.0  # mm kept from the table's edge
MAX_HEIGHT = 120.0  # mm: the robot carries blocks at 200 mm (rules/commands.yaml)


@dataclass
class _Structure:
    """One structure: its objects, where it stands (footprint) and how it is built."""

    kind: str
    objects: dict[str, str] = field(default_factory=dict)  # name -> shape
    footprint: tuple[float, float, float, float] = (0, 0, 0, 0)  # x0, x1, y0, y1 when built
    achieves: list[dict] = field(default_factory=list)  # {"obj", "on", "at"?}
    carriers: dict[str, tuple] = field(default_factory=dict)  # name -> footprint it needs


@dataclass(frozen=True)
class Generated:
    """A generated scenario: its YAML text and what it contains."""

    seed: int
    level: str
    structures: tuple[str, ...]
    touches: int
    distractors: int
    text: str
    family: str = "classic"

    def scenario(self) -> Scenario:
        """The scenario, loaded and validated."""
        return load_text(self.text, f"<generated seed {self.seed} {self.level}>")


def footprint(cx: float, cy: float, sx: float, sy: float) -> tuple[float, float, float, float]:
    """Footprint rectangle of a box of size sx x sy centred at cx, cy."""
    return (cx - sx / 2, cx + sx / 2, cy - sy / 2, cy + sy / 2)


def _tower(rng: np.random.Generator, tag: str, cx: float, cy: float) -> _Structure:
    """Two or three blocks stacked, the widest at the bottom."""
    st = _Structure("tower")
    while True:
        shapes = list(rng.choice(["cube", "brick", "block", "disc"], size=int(rng.integers(2, 4))))
        if sum(CATALOGUE[s][2] for s in shapes) <= MAX_HEIGHT:
            break
    shapes.sort(key=lambda s: -CATALOGUE[s][0])
    below = None
    for i, shape in enumerate(shapes, 1):
        name = f"{tag}-b{i}"
        st.objects[name] = shape
        st.achieves.append({"obj": name, "on": "table", "at": [cx, cy]} if below is None
                           else {"obj": name, "on": below})
        below = name
    w = CATALOGUE[shapes[0]]
    st.footprint = footprint(cx, cy, w[0], w[1])
    return st


def _arch(rng: np.random.Generator, tag: str, cx: float, cy: float) -> _Structure:
    """Two brick pillars apart along x and a beam across them."""
    st = _Structure("arch")
    d = float(rng.integers(30, 41)) * 2  # centre distance 60-80 mm: a 30-50 mm gap
    pillars = [f"{tag}-pillar1", f"{tag}-pillar2"]
    xs = [cx - d / 2, cx + d / 2]
    order = rng.permutation(2)
    for k in order:
        st.objects[pillars[k]] = "brick"
        st.achieves.append({"obj": pillars[k], "on": "table", "at": [xs[k], cy]})
    st.objects[f"{tag}-beam"] = "beam"
    st.achieves.append({"obj": f"{tag}-beam", "on": [pillars[k] for k in order]})
    st.footprint = footprint(cx, cy, CATALOGUE["beam"][0], CATALOGUE["beam"][1])
    return st


def _table(rng: np.random.Generator, tag: str, cx: float, cy: float) -> _Structure:
    """Four brick legs and a plate on all four (Build Table, Fig. 18)."""
    st = _Structure("table")
    dx, dy = float(rng.integers(40, 46)), float(rng.integers(30, 36))
    corners = [(-dx, -dy), (-dx, dy), (dx, dy), (dx, -dy)]
    legs = []
    for k in rng.permutation(4):
        name = f"{tag}-leg{k + 1}"
        st.objects[name] = "brick"
        st.achieves.append({"obj": name, "on": "table",
                            "at": [cx + corners[k][0], cy + corners[k][1]]})
        legs.append(name)
    st.objects[f"{tag}-top"] = "plate"
    st.achieves.append({"obj": f"{tag}-top", "on": legs})
    st.footprint = footprint(cx, cy, *CATALOGUE["plate"][:2])
    return st


def _pyramid(rng: np.random.Generator, tag: str, cx: float, cy: float) -> _Structure:
    """A row of two or three cubes along y, each level resting on pairs below it."""
    st = _Structure("pyramid")
    n = int(rng.integers(2, 4))
    gap = float(rng.integers(4, 9))
    pitch = CATALOGUE["cube"][1] + gap
    rows: list[list[str]] = []
    count = 0
    for level in range(n):
        width = n - level
        names = []
        for j in rng.permutation(width):
            count += 1
            name = f"{tag}-c{count}"
            st.objects[name] = "cube"
            if level == 0:
                y = cy + (j - (width - 1) / 2) * pitch
                st.achieves.append({"obj": name, "on": "table", "at": [cx, y]})
            else:
                st.achieves.append({"obj": name, "on": [rows[-1][j], rows[-1][j + 1]]})
            names.append((j, name))
        rows.append([name for _, name in sorted(names)])
    st.footprint = footprint(cx, cy, CATALOGUE["cube"][0], n * pitch - gap)
    return st


def _inverted_arch(rng: np.random.Generator, tag: str, cx: float, cy: float) -> _Structure:
    """A plank loaded with two cubes on the table, then lifted onto a pillar (Fig. 12-14)."""
    st = _Structure("inverted-arch")
    pillar, plank = f"{tag}-pillar", f"{tag}-plank"
    cubes = [f"{tag}-cube1", f"{tag}-cube2"]
    st.objects.update({pillar: "block", plank: "plank", cubes[0]: "cube", cubes[1]: "cube"})
    e = float(rng.integers(40, 56))  # cubes symmetric on the plank: the load balances
    pillar_first = bool(rng.random() < 0.5)
    place_pillar = {"obj": pillar, "on": "table", "at": [cx, cy]}
    loads = [{"obj": c, "on": plank, "dx": s * e} for c, s in zip(cubes, (-1, 1), strict=True)]
    if rng.random() < 0.5:
        loads.reverse()
    st.achieves = ([place_pillar] if pillar_first else []) + loads + \
        ([] if pillar_first else [place_pillar]) + [{"obj": plank, "on": pillar}]
    st.footprint = footprint(cx, cy, *CATALOGUE["plank"][:2])
    st.carriers[plank] = CATALOGUE["plank"][:2]
    return st


BUILDERS: dict[str, Callable[..., _Structure]] = {
    "tower": _tower, "arch": _arch, "table": _table, "pyramid": _pyramid,
    "inverted-arch": _inverted_arch,
}
_SIZE = {"tower": (50, 50), "arch": (130, 40), "table": (120, 100), "pyramid": (40, 136),
         "inverted-arch": (160, 60)}


def clear(fp: tuple, taken: list[tuple]) -> bool:
    """Is footprint ``fp`` on the table and MARGIN away from every taken footprint (room
    for the gripper's fingers)? Every generated or injected placement is tested by this."""
    x0, x1, y0, y1 = fp
    if x0 < TABLE_X[0] + EDGE or x1 > TABLE_X[1] - EDGE or y0 < TABLE_Y[0] + EDGE or \
            y1 > TABLE_Y[1] - EDGE:
        return False
    return all(x1 + MARGIN_X <= a0 or a1 + MARGIN_X <= x0 or y1 + MARGIN_Y <= b0 or
               b1 + MARGIN_Y <= y0 for a0, a1, b0, b1 in taken)


def free_spot(rng: np.random.Generator, size: Sequence[float], taken: list[tuple]) -> tuple:
    """A random integer centre where a box of ``size`` fits clear of ``taken``.

    Returns (x, y, footprint); footprints are (x0, x1, y0, y1) as from ``footprint``.
    The margins leave room for the gripper's fingers beside every box.
    """
    for _ in range(4000):
        cx = float(rng.integers(int(TABLE_X[0]), int(TABLE_X[1]) + 1))
        cy = float(rng.integers(int(TABLE_Y[0]), int(TABLE_Y[1]) + 1))
        fp = footprint(cx, cy, size[0], size[1])
        if clear(fp, taken):
            return cx, cy, fp
    raise Crowded()


class Crowded(Exception):
    """The table is too full for this draw; the generator draws again."""


def _interleave(rng: np.random.Generator, lists: list[list]) -> list:
    """Merge lists at random, keeping each one's order."""
    queues = [list(x) for x in lists if x]
    out = []
    while queues:
        q = queues[int(rng.integers(len(queues)))]
        out.append(q.pop(0))
        queues = [x for x in queues if x]
    return out


def _draw(rng: np.random.Generator) -> tuple[list[_Structure], dict, dict, dict, list]:
    """One attempt: structures, teach/execute positions, distractors and the step list."""
    n = int(rng.choice([1, 1, 2, 2, 3]))
    kinds = [str(k) for k in rng.choice(list(BUILDERS), size=n)]
    taken: list[tuple] = []
    structures = []
    for i, kind in enumerate(kinds, 1):
        cx, cy, fp = free_spot(rng, _SIZE[kind], taken)
        st = BUILDERS[kind](rng, f"{kind.split('-')[0][:3]}{i}", cx, cy)
        taken.append(st.footprint)
        structures.append(st)
    sites = list(taken)
    shapes = {name: s for st in structures for name, s in st.objects.items()}
    distract = {f"other{k}": str(rng.choice(DISTRACTORS)) for k in
                range(1, int(rng.choice([0, 1, 1, 2])) + 1)}
    teach, execute = {}, {}
    for layout in (teach, execute):
        busy = list(sites)
        for name, shape in {**shapes, **distract}.items():
            x, y, fp = free_spot(rng, CATALOGUE[shape][:2], busy)
            busy.append(fp)
            layout[name] = (x, y)
    order = _interleave(rng, [st.achieves for st in structures]) if rng.random() < 0.5 else \
        [a for st in structures for a in st.achieves]
    return structures, teach, execute, distract, order


def _steps(rng: np.random.Generator, order: list[dict], teach: dict) -> tuple[list[dict], int]:
    """pick/place steps, with up to two touches of objects lying alone on the table."""
    steps, touches = [], 0
    moved: set[str] = set()
    carriers = {a["on"] for a in order if isinstance(a["on"], str) and a["on"] != "table"}
    for a in order:
        free = [n for n in list(teach) if n not in moved and n not in carriers and n != a["obj"]]
        if touches < 2 and free and rng.random() < 0.2:
            steps.append({"touch": str(rng.choice(sorted(free)))})
            touches += 1
        elif touches < 2 and rng.random() < 0.1:  # touch what is about to be picked
            steps.append({"touch": a["obj"]})
            touches += 1
        steps.append({"pick": a["obj"]})
        place = {"place": a["obj"], "on": a["on"]}
        if "at" in a:
            place["at"] = a["at"]
        elif "dx" in a:  # on the plank where it lies now (the inverted arch's loading)
            px, py = teach[a["on"]]
            place["at"] = [px + a["dx"], py]
        steps.append(place)
        moved.add(a["obj"])
    return steps, touches


def generate(seed: int, level: str = "nominal", structures: Sequence[str] | None = None
             ) -> Generated:
    """A random, physically feasible scenario; the same ``seed`` gives the same text."""
    if level not in LEVELS:
        raise ValueError(f"unknown noise level {level!r} (levels: {', '.join(LEVELS)})")
    rng = np.random.default_rng(seed)
    for _ in range(100):
        try:
            sts, teach, execute, distract, order = _draw(rng)
        except Crowded:
            continue
        if structures is not None and [s.kind for s in sts] != list(structures):
            continue
        steps, touches = _steps(rng, order, teach)
        text = _yaml(seed, level, sts, teach, execute, distract, steps)
        return Generated(seed, level, tuple(s.kind for s in sts), touches, len(distract), text)
    raise ValueError(f"seed {seed}: no layout found for structures {structures}")


def _num(v: float) -> str:
    """A coordinate as YAML (integers without a trailing .0)."""
    return str(int(v)) if float(v).is_integer() else f"{v:g}"


def _yaml(seed: int, level: str, sts: list[_Structure], teach: dict, execute: dict,
          distract: dict, steps: list[dict]) -> str:
    """The scenario file text (design.md format)."""
    k = LEVELS[level]
    base = Noise()
    kinds = ", ".join(s.kind for s in sts)
    shapes = sorted({*(s for st in sts for s in st.objects.values()), *distract.values()})
    lines = [f"# Generated by perception.world.generator (seed {seed}, noise {level}): {kinds};",
             f"# {len(distract)} irrelevant object(s).",
             f"name: gen-{seed}-{level}", f"seed: {seed}", "shapes:"]
    lines += [f"  {s}: [{', '.join(map(str, CATALOGUE[s]))}]" for s in shapes]
    lines += ["noise:", f"  pixel: {base.pixel * k:g}", f"  tremor: {base.tremor * k:g}",
              f"  speed: [{base.speed[0]:g}, {base.speed[1]:g}]"]
    all_shapes = {n: s for st in sts for n, s in st.objects.items()} | distract
    lines += ["teach:", "  objects:"]
    lines += [f"    {n}: {{shape: {all_shapes[n]}, at: [{_num(x)}, {_num(y)}]}}"
              for n, (x, y) in teach.items()]
    lines.append("  demonstration:")
    for step in steps:
        kind = next(iter(step))
        lines.append(f"    - {kind}: {step[kind]}")
        if kind == "place":
            on = step["on"]
            lines.append(f"      on: {on if isinstance(on, str) else '[' + ', '.join(on) + ']'}")
            if "at" in step:
                lines.append(f"      at: [{_num(step['at'][0])}, {_num(step['at'][1])}]")
    lines += ["execute:", "  objects:"]
    lines += [f"    x-{n}: {{shape: {all_shapes[n]}, at: [{_num(x)}, {_num(y)}]}}"
              for n, (x, y) in execute.items()]
    return "\n".join(lines) + "\n"
