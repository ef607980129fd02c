"""Issue #6 sweep: one learned plan, executed in many random execution layouts.

For build-table and inverted-arch the plan is learned once by watching the
bundled demonstration (`lbw run`'s pipeline), then executed in N seeded random
execution workspaces (the same objects scattered elsewhere on the table, clear
of where the taught structure stands). Reports the success rate and every
failure. Run: ``python -m bench layouts`` (or ``python bench/bench_layouts.py
--count 20``).

``--tight`` (issue #12): the objects stand in one row along x or y, 0-10 mm
apart, so no finger fits between neighbours along the row: the jaws must close
across it. ``--scenario NAME`` picks one bundled scenario.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np
import yaml

from lbw_engine.do import plan as planmod
from lbw_engine.paths import bundled_scenario
from lbw_engine.rules import load_rules
from lbw_engine.yamlio import load_file, plain

SCENARIOS = ("build-table", "inverted-arch")
def random_layout(scenario: Any, seed: int) -> dict[str, dict[str, Any]]:
    """Execution objects of ``scenario`` scattered at random, clear of the final structure.

    Spots come from the scenario generator's ``free_spot``, whose margins leave
    room for the gripper's fingers beside every box.
    """
    from perception.world.generator import footprint, free_spot

    rng = np.random.default_rng(seed)
    final = scenario.states[-1]
    taken = [footprint(c[0], c[1], final.size[n][0], final.size[n][1])
             for n, c in final.center.items() if final.support.get(n) != ("table",)
             or any(n in s for s in final.support.values())]
    objects = (scenario.execute or scenario.teach).objects
    layout: dict[str, dict[str, Any]] = {}
    for name, spec in sorted(objects.items(), key=lambda kv: -kv[1].size[0] * kv[1].size[1]):
        x, y, fp = free_spot(rng, spec.size[:2], taken)
        taken.append(fp)
        layout[name] = {"shape": spec.shape, "at": [x, y]}
    return layout


TIGHT_GAP = (0.0, 10.0)  # mm between neighbours in a tight row
ROW_CLEARANCE = 40.0  # mm between a tight row and the taught structure's footprint


def tight_layout(scenario: Any, seed: int) -> dict[str, dict[str, Any]]:
    """Execution objects of ``scenario`` in one row along x or y, 0-10 mm apart.

    The row stands clear of where the taught structure will stand (its final
    footprints grown by ROW_CLEARANCE) and EDGE from the table's edges.
    """
    from lbw_engine.model.geometry import TABLE_X, TABLE_Y
    from perception.world.generator import EDGE

    rng = np.random.default_rng(seed)
    final = scenario.states[-1]
    built = [(c[0] - final.size[n][0] / 2 - ROW_CLEARANCE, c[0] + final.size[n][0] / 2
              + ROW_CLEARANCE, c[1] - final.size[n][1] / 2 - ROW_CLEARANCE,
              c[1] + final.size[n][1] / 2 + ROW_CLEARANCE) for n, c in final.center.items()]
    objects = (scenario.execute or scenario.teach).objects
    names = sorted(objects)
    rng.shuffle(names)  # the row's order is drawn too
    for _ in range(2000):
        axis = int(rng.integers(2))
        gaps = rng.uniform(*TIGHT_GAP, size=len(names))
        x, y = float(rng.uniform(*TABLE_X)), float(rng.uniform(*TABLE_Y))
        layout, boxes, cursor = {}, [], (x, y)[axis]
        for name, gap in zip(names, gaps, strict=True):
            sx, sy = objects[name].size[:2]
            length = (sx, sy)[axis]
            c = [x, y]
            c[axis] = cursor + length / 2
            cursor += length + gap
            layout[name] = {"shape": objects[name].shape,
                            "at": [round(float(c[0]), 1), round(float(c[1]), 1)]}
            boxes.append((c[0] - sx / 2, c[0] + sx / 2, c[1] - sy / 2, c[1] + sy / 2))
        on_table = all(TABLE_X[0] + EDGE <= b[0] and b[1] <= TABLE_X[1] - EDGE and
                       TABLE_Y[0] + EDGE <= b[2] and b[3] <= TABLE_Y[1] - EDGE for b in boxes)
        apart = all(b[1] <= a[0] or a[1] <= b[0] or b[3] <= a[2] or a[3] <= b[2]
                    for b in boxes for a in built)
        if on_table and apart:
            return layout
    raise RuntimeError(f"no tight row fits for seed {seed}")


def with_layout(path: Any, layout: dict[str, dict[str, Any]], seed: int) -> Any:
    """The scenario at ``path`` with ``layout`` as its execute workspace."""
    from perception.world.scenario import load_text

    doc = plain(load_file(path))
    doc["execute"] = {"objects": layout}
    doc["seed"] = seed
    return load_text(yaml.safe_dump(doc, sort_keys=False), f"{path}#layout-{seed}")


def sweep(name: str, count: int, first_seed: int = 1, tight: bool = False) -> dict[str, Any]:
    """Learn ``name``'s plan by watching, then execute it in ``count`` random layouts."""
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.pipeline.run import run as pipeline
    from perception.world.scenario import load

    path = bundled_scenario(name)
    learned = pipeline(load(path))
    if learned.plan is None:
        return {"scenario": name, "learned": False, "failure": learned.failure}
    plan = planmod.parse(learned.plan, file="plan.json")
    crules = load_rules()
    scenario = load(path)
    failures, commands, seconds = [], [], []
    for seed in range(first_seed, first_seed + count):
        layout = (tight_layout if tight else random_layout)(scenario, seed)
        sc = with_layout(path, layout, seed)
        clock = time.perf_counter()
        result = execute_plan(plan, sc, crules)
        seconds.append(time.perf_counter() - clock)
        commands.append(result.report.get("commands", 0))
        if not result.success:
            failures.append({"seed": seed, "message": result.message})
    ok = count - len(failures)
    return {"scenario": name, "learned": True, "layouts": count, "succeeded": ok,
            "success_rate": ok / count, "commands": sorted(set(commands)),
            "seconds_per_execution": round(sum(seconds) / len(seconds), 2),
            "failures": failures}


def main(argv: list[str]) -> dict[str, Any]:
    """Run the sweep for every scenario and print one line each."""
    parser = argparse.ArgumentParser(prog="bench layouts")
    parser.add_argument("--count", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tight", action="store_true",
                        help="objects in one row, 0-10 mm apart (issue #12)")
    parser.add_argument("--scenario", choices=SCENARIOS, action="append")
    args = parser.parse_args(argv)
    figures = {}
    print(f"{'scenario':<15}{'layouts':>8}{'verified':>9}{'commands':>10}{'s/run':>7}"
          + ("  (tight rows)" if args.tight else ""))
    for name in args.scenario or SCENARIOS:
        fig = sweep(name, args.count, args.seed, args.tight)
        figures[name] = fig
        if not fig["learned"]:
            print(f"{name:<15} plan not learned: {fig['failure']}")
            continue
        print(f"{name:<15}{fig['layouts']:>8}{fig['succeeded']:>9}"
              f"{','.join(map(str, fig['commands'])):>10}{fig['seconds_per_execution']:>7}")
        for f in fig["failures"]:
            print(f"   seed {f['seed']}: {f['message']}")
    return figures


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
