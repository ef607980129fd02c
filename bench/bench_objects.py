"""Object-finder on generated workspaces: misses, phantoms, wrong shapes, position errors.

Each generated scenario (perception.world.generator) has a teach and an execute
workspace; both initial states are built in the simulated world, settled,
rendered at the scenario's pixel noise and handed to the object-finder
(Sec. III-B, Sec. VII-A). Found objects are matched to the true boxes
(nearest centre within MATCH_MM, shape-blind) and counted. Run:
``python -m bench.bench_objects --count 100 --seed 1000 --verbose`` (or
``python -m bench objects``).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass, field

import numpy as np

from perception.vision.camera import default_cameras
from perception.vision.frames import Frame
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources
from perception.world.generator import LEVELS, generate
from perception.world.physics import World
from perception.world.render import Renderer
from perception.world.scenario import ObjectSpec

MATCH_MM = 25.0  # a found centre farther than this from every true box is a phantom


@dataclass
class Tally:
    """Counts over many workspaces."""

    workspaces: int = 0
    blocks: int = 0
    misses: int = 0
    phantoms: int = 0
    wrong_shape: int = 0
    errors: list[float] = field(default_factory=list)
    times: list[float] = field(default_factory=list)
    bad: list[str] = field(default_factory=list)


def _specs(sc, which: str) -> list[ObjectSpec]:
    """The boxes of one workspace: teach, execute, or the taught final structure."""
    if which in ("teach", "execute"):
        return list((sc.teach if which == "teach" else sc.execute).objects.values())
    final = sc.states[-1]
    return [ObjectSpec(n, sc.teach.objects[n].shape, final.size[n], final.center[n],
                       final.support[n]) for n in final.center]


def truth_and_frame(seed: int, level: str, which: str, family: str = "classic"
                    ) -> tuple[list, dict, Frame]:
    """True (shape, centre) pairs, the shape database and the rendered frame of ``which``
    (the scenario of generator ``family``)."""
    if which.startswith("layout-"):  # bench_layouts' random execute workspaces
        from bench.bench_layouts import random_layout, with_layout
        from lbw_engine.paths import bundled_scenario
        from perception.world.scenario import load

        path = bundled_scenario(which.removeprefix("layout-"))
        sc = with_layout(path, random_layout(load(path), seed), seed)
        which = "execute"
    else:
        sc = generate(seed, level, family=family).scenario()
    specs = _specs(sc, which)
    world = World(specs)
    world.settle(0.5)
    pos = world.positions()
    truth = [(spec.shape, pos[spec.name]) for spec in specs]
    imgs = Renderer(default_cameras(), pixel_noise=sc.noise.pixel, seed=sc.seed).render(
        world.scene())
    return truth, dict(sc.shapes), Frame(0, 0.0, imgs["top"], imgs["side"])


def score(truth: list, found: list) -> tuple[int, int, int, list[float]]:
    """Misses, phantoms, wrong shapes and position errors of ``found`` against ``truth``."""
    pairs = sorted((float(np.linalg.norm(np.subtract(f.position, t[1]))), i, j)
                   for i, t in enumerate(truth) for j, f in enumerate(found))
    used_t: set[int] = set()
    used_f: set[int] = set()
    errors, wrong = [], 0
    for d, i, j in pairs:
        if d > MATCH_MM or i in used_t or j in used_f:
            continue
        used_t.add(i)
        used_f.add(j)
        errors.append(d)
        wrong += found[j].shape != truth[i][0]
    return len(truth) - len(used_t), len(found) - len(used_f), wrong, errors


def run(seeds: range, levels: list[str], sets: list[str],
        families: tuple[str, ...] = ("classic",)) -> dict[str, Tally]:
    """Evaluate the finder on both workspaces of every seed at every level; the k-th seed
    is of family ``families[k % len(families)]``."""
    cams = default_cameras()
    out: dict[str, Tally] = {}
    for level in levels:
        t = out.setdefault(level, Tally())
        for k, seed in enumerate(seeds):
            family = families[k % len(families)]
            for which in sets:
                truth, shapes, frame = truth_and_frame(seed, level, which, family)
                start = time.perf_counter()
                found = ObjectFinder(cams, VisionResources()).find(frame, shapes)
                t.times.append(time.perf_counter() - start)
                miss, ghost, wrong, errs = score(truth, found)
                t.workspaces += 1
                t.blocks += len(truth)
                t.misses += miss
                t.phantoms += ghost
                t.wrong_shape += wrong
                t.errors += errs
                if miss or ghost or wrong or (errs and max(errs) > 5.0):  # any error > 5 mm
                    t.bad.append(f"{seed}/{family}/{which}: miss {miss} phantom {ghost} "
                                 f"shape {wrong} max err {max(errs, default=0):.1f}")
    return out


def main(argv: list[str]) -> dict:
    """Run the sweep, print one line per level (and the failing workspaces), return figures."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--count", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--levels", default=",".join(LEVELS))
    ap.add_argument("--sets", default="teach,execute",
                    help="teach, execute, final (the built structures), "
                         "layout-build-table, layout-inverted-arch")
    ap.add_argument("--families", default="classic",
                    help="generator families taken in turn, comma-separated, or 'all'")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args(argv)
    from perception.world.generator import FAMILIES

    families = FAMILIES if args.families == "all" else tuple(args.families.split(","))
    unknown = [f for f in families if f not in FAMILIES]
    if unknown:
        ap.error(f"--families: unknown {', '.join(unknown)} (known: {', '.join(FAMILIES)})")
    tallies = run(range(args.seed, args.seed + args.count), args.levels.split(","),
                  args.sets.split(","), families)
    figures: dict[str, float] = {}
    for level, t in tallies.items():
        e = np.array(t.errors or [0.0])
        row = {"workspaces": t.workspaces, "blocks": t.blocks, "wrong_workspaces": len(t.bad),
               "misses": t.misses,
               "phantoms": t.phantoms, "wrong_shape": t.wrong_shape,
               "err_median_mm": float(np.median(e)), "err_p95_mm": float(np.percentile(e, 95)),
               "ms_median": 1000 * float(np.median(t.times)),
               "ms_max": 1000 * float(np.max(t.times))}
        print(f"   {level:8s} " + "  ".join(f"{k} {v:.4g}" for k, v in row.items()))
        for line in t.bad if args.verbose else t.bad[:10]:
            print(f"      {line}")
        figures.update({f"{level}_{k}": float(v) for k, v in row.items()})
    return figures


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
