"""Vision benchmark: renderer speed (real-time factor at 30 fps) and detector costs."""

from __future__ import annotations

import time

import numpy as np

from perception.camera import default_cameras
from perception.render import Renderer
from perception.scene import Box

FPS = 30.0


def build_table_scene(k: int, rng: np.random.Generator) -> list[Box]:
    """Frame ``k`` of a Build-Table-like scene: five blocks, a hand moving with tremor."""
    blocks = [Box("block", (-150, 200, 25), (30, 30, 50)),
              Box("block", (-100, 320, 25), (30, 30, 50)),
              Box("block", (-220, 100, 25), (30, 30, 50)),
              Box("block", (220, 100, 25), (30, 30, 50)),
              Box("block", (150, 220, 5), (120, 100, 10))]
    s = (k % 240) / 240.0
    x = -200 + 400 * s + rng.normal(0, 1.0)
    y = 150 + 100 * np.sin(2 * np.pi * s) + rng.normal(0, 1.0)
    z = 90 + 60 * np.cos(2 * np.pi * s) + rng.normal(0, 1.0)
    hand = [Box("hand", (x, y, z + 35), (50, 50, 30)), Box("hand", (x - 20, y, z), (10, 20, 40)),
            Box("hand", (x + 20, y, z), (10, 20, 40))]
    return hand + blocks


def bench_render(frames: int = 1000, repeats: int = 5) -> dict:
    """Frames per second of ``Renderer.render`` on a moving-hand scene (best of repeats)."""
    rng = np.random.default_rng(0)
    scenes = [build_table_scene(k, rng) for k in range(frames * repeats)]
    renderer = Renderer(default_cameras(), pixel_noise=2.0, seed=0)
    renderer.render(scenes[0])
    times = []
    for r in range(repeats):  # fresh hand poses every frame: no cache hits for the hand
        t0 = time.perf_counter()
        for scene in scenes[r * frames:(r + 1) * frames]:
            renderer.render(scene)
        times.append((time.perf_counter() - t0) / frames)
    dt = float(np.median(times))
    return {"render_us_per_frame": dt * 1e6, "render_fps": 1.0 / dt,
            "render_realtime_factor": 1.0 / dt / FPS}


def main(argv: list[str]) -> dict:
    """Run the vision benchmarks, print a table and return the figures."""
    figures = bench_render()
    for key, value in figures.items():
        print(f"   {key:32s} {value:12.1f}")
    return figures
