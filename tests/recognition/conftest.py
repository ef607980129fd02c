"""Recognize each bundled scenario once per test session (module-scoped results)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from perception.vision.camera import default_cameras
from perception.vision.envnodes.registry import watch_frames
from perception.world.demonstrator import Demonstration
from perception.world.groundtruth import ground_truth
from perception.world.scenario import load
from perception.world.stream import demonstration_frames, teach_names

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
    span: tuple[float, float]  # first and last time part of the hand is in both views


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
    seen: list[float] = []
    frames = demonstration_frames(sc, cams, demonstration=_noting_hand(demo, cams, seen))
    rec, hand = watch_frames(frames, cams, sc.shapes, RULES, teach_names(sc))
    return Watched(sc, demo, to_actions(rec), ground_truth(sc, RULES, Demonstration(sc)),
                   hand.sight.pixels, (seen[0], seen[-1]) if seen else (0.0, 0.0))


def _noting_hand(demo: Demonstration, cams: dict, seen: list[float]):
    """The demonstration's (t, scene) frames, noting the times some part of the true hand
    (palm or a finger box) is inside both camera images (for the evaluation only)."""
    signs = np.array([[sx, sy, sz] for sx in (-.5, .5) for sy in (-.5, .5) for sz in (-.5, .5)])
    for t, scene in demo:
        boxes = [b for b in scene if b.kind == "hand"]
        if boxes and all(any(_in_image(cam, np.asarray(b.center) + signs * np.asarray(b.size))
                             for b in boxes) for cam in cams.values()):
            seen.append(t)
        yield t, scene


def _in_image(cam, corners: np.ndarray) -> bool:
    """Whether the projected box (its corners' bounding rectangle) meets the image."""
    uv = cam.project(corners)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    return bool(hi[0] >= 0 and hi[1] >= 0 and lo[0] < cam.size[0] and lo[1] < cam.size[1])


def visible_span(w: Watched) -> tuple[float, float]:
    """First and last time part of the true hand is inside both camera images (it enters and
    leaves from outside the cameras' view, design.md; before and after nothing can see it)."""
    return w.span


_CACHE: dict[str, Watched] = {}


@pytest.fixture(scope="module")
def watched():
    """name -> Watched, each scenario recognized at most once per worker."""

    def get(name: str) -> Watched:
        if name not in _CACHE:
            _CACHE[name] = watch(name)
        return _CACHE[name]

    return get
