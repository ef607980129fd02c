"""Vision benchmark: renderer speed (real-time factor at 30 fps) and detector costs."""

from __future__ import annotations

import time

import numpy as np

from perception.vision.camera import default_cameras
from perception.vision.frames import Frame
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.change import ChangeDetector
from perception.vision.vfd.hand import HandTracker
from perception.vision.vfd.motion import MotionDetector
from perception.vision.vfd.objects import ObjectFinder
from perception.vision.vfd.resources import VisionResources
from perception.vision.vfd.search import SilFinder, visual_search
from perception.world.render import Renderer
from perception.world.scene import Box

FPS = 30.0


def build_table_scene(k: int, rng: np.random.Generator) -> list[Box]:
    """Frame ``k`` of a Build-Table-like scene: five blocks, a hand moving with tremor."""
    blocks = [Box("block", (-150, 200, 25), (30, 30, 50)),
              Box("block", (-100, 320, 25), (30, 30, 50)),
              Box("block", (-220, 100, 25), (30, 30, 50)),
              Box("block", (220, 100, 25), (30, 30, 50)),
              Box("block", (150, 220, 5), (120, 100, 10))]
    s = (k % 240) / 240.0
    x = float(-200 + 400 * s + rng.normal(0, 1.0))
    y = float(150 + 100 * np.sin(2 * np.pi * s) + rng.normal(0, 1.0))
    z = float(90 + 60 * np.cos(2 * np.pi * s) + rng.normal(0, 1.0))
    # The gripper of perception.world.hand: grip centre (x, y, z), fingertips 10 mm below it.
    hand = [Box("hand", (x, y, z + 55), (50, 50, 30)),
            Box("hand", (x - 35, y, z + 15), (10, 20, 50)),
            Box("hand", (x + 35, y, z + 15), (10, 20, 50))]
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


def _frames(n: int) -> tuple[list[Frame], list[np.ndarray]]:
    """Rendered frames of the moving-hand scene and the true grip centres."""
    rng = np.random.default_rng(1)
    renderer = Renderer(default_cameras(), pixel_noise=2.0, seed=1)
    frames, truth = [], []
    for k in range(n):
        scene = build_table_scene(k, rng)
        imgs = renderer.render(scene)
        frames.append(Frame(k, k / FPS, imgs["top"], imgs["side"]))
        palm = scene[0].center
        truth.append(np.array([palm[0], palm[1], palm[2] - 55.0]))
    return frames, truth


def _time(fn, repeats: int = 20) -> float:
    """Median wall time of ``fn()`` in microseconds."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)) * 1e6


def bench_detectors(n: int = 480) -> dict:
    """Per-frame cost and pixels read by the always-on detectors, plus one-shot detectors."""
    cams = default_cameras()
    frames, truth = _frames(n)
    res = VisionResources()
    md, ht = MotionDetector(cams, res), HandTracker(cams, res)
    md.start()
    t_md = t_ht = 0.0
    errors = []
    for frame, p in zip(frames, truth, strict=True):
        t0 = time.perf_counter()
        md.update(frame)
        t1 = time.perf_counter()
        if md.found():
            ht.stimulate(md.target())
        ht.update(frame)
        t2 = time.perf_counter()
        t_md, t_ht = t_md + t1 - t0, t_ht + t2 - t1
        res.end_frame()
        if ht.position is not None and frame.index > 30:
            errors.append(np.linalg.norm(ht.position - p))
    full = 2 * 256 * 256
    frame = frames[0]
    shapes = {"brick": [30, 30, 50], "plate": [120, 100, 10]}
    cd = ChangeDetector(cams, VisionResources())
    cd.attention(Region3D.around((-150, 200, 25), (35, 35, 55)))
    cd.snapshot(frame)
    return {
        "motion_detector_us_per_frame": t_md / n * 1e6,
        "hand_tracker_us_per_frame": t_ht / n * 1e6,
        "pixels_read_fraction_of_two_frames": float(np.mean(res.history)) / full,
        "hand_error_mm_median": float(np.median(errors)),
        "hand_error_mm_p95": float(np.percentile(errors, 95)),
        "visual_search_us": _time(lambda: visual_search(SilFinder(cams, VisionResources()),
                                                        frame, (-150, 200, 150))),
        "change_compare_us": _time(lambda: cd.compare(frames[1])),
        "object_finder_ms": _time(lambda: ObjectFinder(cams, VisionResources()).find(
            frame, shapes), 3) / 1000.0,
    }


def bench_demonstration(name: str = "build-table") -> dict:
    """Motion-detector + hand-tracker on a bundled demonstration, against the true hand."""
    from pathlib import Path

    from perception.world.demonstrator import Demonstration
    from perception.world.scenario import load

    sc = load(Path(__file__).resolve().parent.parent / "scenarios" / f"{name}.yaml")
    cams = default_cameras()
    renderer = Renderer(cams, pixel_noise=sc.noise.pixel, seed=sc.seed)
    res = VisionResources()
    md, ht = MotionDetector(cams, res), HandTracker(cams, res)
    md.start()
    errors, untracked, settle = [], 0, 0
    for k, (_, scene) in enumerate(Demonstration(sc)):
        imgs = renderer.render(scene)
        frame = Frame(k, k / FPS, imgs["top"], imgs["side"])
        md.update(frame)
        if md.found() and ht.stimulate(md.target()):
            settle = 6  # the windows converge over a few frames after a placement
        ht.update(frame)
        res.end_frame()
        palm = [b for b in scene if b.kind == "hand" and b.name == "palm"]
        if not palm:
            continue
        if ht.position is None:
            untracked += 1
        elif settle > 0:
            settle -= 1
        else:  # the grip centre lies 55 mm below the palm centre (perception.world.hand)
            errors.append(float(np.linalg.norm(ht.position - np.subtract(palm[0].center,
                                                                           (0, 0, 55)))))
    return {f"demo_{name}_hand_error_mm_median": float(np.median(errors)),
            f"demo_{name}_hand_error_mm_p95": float(np.percentile(errors, 95)),
            f"demo_{name}_untracked_frames": float(untracked),
            f"demo_{name}_pixels_read_fraction": float(np.mean(res.history)) / (2 * 256 * 256)}


def main(argv: list[str]) -> dict:
    """Run the vision benchmarks, print a table and return the figures."""
    figures = bench_render()
    figures.update(bench_detectors())
    figures.update(bench_demonstration())
    for key, value in figures.items():
        print(f"   {key:36s} {value:12.4g}")
    return figures
