"""Seeded random scenarios, in named families: stress the pipeline on unseen layouts.

``generate(seed, level, structures, family)`` writes a scenario file (design.md
format). The ``classic`` family (``perception.world.generator.classic``, the
default) builds towers, arches, tables, pyramids and inverted arches with wide
gaps; the other families (``perception.world.generator.families``) cover each
class of layout of issue #12: structures along x as well as y, 0-10 mm gaps,
ALIGN on any face, small blocks, tall thin pillars, long crossing beams,
bridges, plates on three supports, staircases, stacked initial layouts and
rearrangement. ``FAMILIES`` lists them in a fixed order; ``family_of`` is how
a benchmark deals them out so a seed always draws the same mix.

Every family scenario is checked before it is returned: it loads (the loader
replays the demonstration symbolically: table bounds, overlaps, supports), its
structures and stacks stay under MAX_HEIGHT, and its shapes are pairwise
distinguishable by size (the object-finder matches by shape). A draw that fails
a check is drawn again from the same generator, so the result depends on the
seed alone. Draws of the families in ``SIMULATED`` are also simulated (``stands``);
tests/generator simulates a few of every family.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from lbw_engine.errors import InputError
from perception.world.generator.assemble import draw, to_yaml
from perception.world.generator.classic import (
    BUILDERS,
    CATALOGUE,
    LEVELS,
    MAX_HEIGHT,
    Crowded,
    Generated,
    clear,
    footprint,
    free_spot,
)
from perception.world.generator.classic import generate as _classic
from perception.world.generator.families import FAMILY_BUILDERS, SIMULATED
from perception.world.scenario import Scenario, load_text

__all__ = ["BUILDERS", "CATALOGUE", "FAMILIES", "LEVELS", "Crowded", "Generated", "clear",
           "distinguishable",
           "family_of", "footprint", "free_spot", "generate"]

FAMILIES: tuple[str, ...] = ("classic", *FAMILY_BUILDERS)


def family_of(index: int, families: Sequence[str] = FAMILIES) -> str:
    """The family of the ``index``-th scenario of a benchmark: every noise level
    (index % 3) sees every family in turn."""
    return families[(index // len(LEVELS)) % len(families)]


def distinguishable(a: Sequence[float], b: Sequence[float]) -> bool:
    """Do two box sizes differ by >= 20 mm on one axis or >= 10 mm on two?"""
    d = sorted((abs(x - y) for x, y in zip(a, b, strict=True)), reverse=True)
    return d[0] >= 20 or d[1] >= 10


def generate(seed: int, level: str = "nominal", structures: Sequence[str] | None = None,
             family: str = "classic") -> Generated:
    """A random, physically feasible scenario of ``family``; the same arguments give the
    same text. ``structures`` (classic family only) asks for these structure kinds."""
    if family == "classic":
        return _classic(seed, level, structures)
    if family not in FAMILY_BUILDERS:
        raise ValueError(f"unknown family {family!r} (families: {', '.join(FAMILIES)})")
    if structures is not None:
        raise ValueError("structures can be asked for in the classic family only")
    if level not in LEVELS:
        raise ValueError(f"unknown noise level {level!r} (levels: {', '.join(LEVELS)})")
    rng = np.random.default_rng(seed)
    for _ in range(200):
        try:
            d = draw(rng, family)
        except Crowded:
            continue
        text = to_yaml(d, seed, level)
        try:
            sc = load_text(text, f"<generated seed {seed} {family}>")
        except InputError:
            continue  # e.g. an align slide ending on a neighbour: draw again
        if _feasible(sc) and (family not in SIMULATED or stands(sc)):
            return Generated(seed, level, tuple(p.kind for p in d.pieces), d.touches,
                             len(d.distract), text, family)
    raise ValueError(f"seed {seed}: no feasible layout found for family {family}")


def _feasible(sc: Scenario) -> bool:
    """Heights under MAX_HEIGHT in both initial layouts and at the end; shapes told apart."""
    def top(center: Sequence[float], shape: str) -> float:
        return center[2] + sc.shapes[shape][2] / 2

    ws = [sc.teach.objects.values(), sc.execute.objects.values()]
    tops = [top(o.center, o.shape) for w in ws for o in w]
    tops += [top(sc.states[-1].center[n], o.shape) for n, o in sc.teach.objects.items()]
    sizes = list(sc.shapes.values())
    return max(tops) <= MAX_HEIGHT and all(
        distinguishable(a, b) for i, a in enumerate(sizes) for b in sizes[i + 1:])


def stands(sc: Scenario, tolerance: float = 3.0) -> bool:
    """Does the simulated demonstration build the replayed structure, at rest?

    Physics (perception.world.physics) under the demonstrator's hand: every box ends
    within ``tolerance`` mm of its replayed centre and stays there while the world settles.
    """
    from perception.world.demonstrator import Demonstration

    demo = Demonstration(sc)
    for _ in demo:
        pass
    before = demo.world.positions()
    demo.world.settle(1.0)
    after = demo.world.positions()
    return all(math.dist(c, sc.states[-1].center[n]) < tolerance and
               math.dist(c, before[n]) < 1.0 for n, c in after.items())
