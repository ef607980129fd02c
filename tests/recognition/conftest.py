"""Recognize each bundled scenario once per test session (module-scoped results)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from lbw_engine.actions import to_actions
from lbw_engine.rules import load_rules
from perception.camera import default_cameras
from perception.demonstrator import Demonstration
from perception.envnodes import watch_frames
from perception.groundtruth import ground_truth
from perception.scenario import load
from perception.stream import demonstration_frames, teach_names

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = sorted(p.stem for p in (ROOT / "scenarios").glob("*.yaml"))
RULES = load_rules()


@dataclass
class Watched:
    """One recognized demonstration with its ground truth."""

    scenario: object
    demo: Demonstration
    actions: dict
    truth: list
    pixels: list[int]


def watch(name: str, pixel: float | None = None, tremor: float | None = None) -> Watched:
    """Simulate, render and recognize the scenario ``name`` (optionally noisier)."""
    sc = load(ROOT / "scenarios" / f"{name}.yaml")
    if pixel is not None or tremor is not None:
        from dataclasses import replace
        noise = replace(sc.noise, pixel=pixel if pixel is not None else sc.noise.pixel,
                        tremor=tremor if tremor is not None else sc.noise.tremor)
        sc = replace(sc, noise=noise)
    demo = Demonstration(sc)
    cams = default_cameras()
    frames = demonstration_frames(sc, cams, demonstration=demo)
    rec, eyes = watch_frames(frames, cams, sc.shapes, RULES, teach_names(sc))
    return Watched(sc, demo, to_actions(rec), ground_truth(sc, Demonstration(sc)), eyes.pixels)


def visible_span(w: Watched) -> tuple[float, float]:
    """First and last time part of the true hand is inside both camera images (it enters and
    leaves from outside the cameras' view, design.md; before and after nothing can see it)."""
    cams = default_cameras()
    demo = Demonstration(w.scenario)
    demo._cursor = 0  # target() looks segments up from a cursor that iteration starts
    seen = []
    for k in range(demo.n_frames):
        t = k / demo.fps
        p, seg = demo.target(t)
        if seg.phase == "absent":
            continue
        # any part of the hand: the palm reaches 25 mm to either side of the grip point
        pts = np.array([p]) + np.array([[-25.0, 0, 0], [0, 0, 0], [25.0, 0, 0]])
        ok = any(all(np.all(uv >= 0) and np.all(uv < c.size) for c in cams.values()
                     for uv in [c.project(pt[None])[0]]) for pt in pts)
        if ok:
            seen.append(t)
    return seen[0], seen[-1]


_CACHE: dict[str, Watched] = {}


@pytest.fixture(scope="module")
def watched():
    """name -> Watched, each scenario recognized at most once per worker."""

    def get(name: str) -> Watched:
        if name not in _CACHE:
            _CACHE[name] = watch(name)
        return _CACHE[name]

    return get
