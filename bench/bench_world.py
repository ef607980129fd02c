"""World benchmark: demonstration simulation (and rendering) speed as a real-time factor.

For each bundled scenario: play the whole demonstration at 30 fps (physics
stepped between frames), once simulating only and once also rendering both
camera views; report demonstrated seconds per wall-clock second (best of three
runs). Target (issue #3): >= 200x real time for simulation and rendering
together. The same ratio in CPU seconds of this process is reported too: on a
shared machine other processes stretch wall time, not CPU time.
"""

from __future__ import annotations

import time
from pathlib import Path

from perception.vision.camera import default_cameras
from perception.world.demonstrator import Demonstration
from perception.world.render import Renderer
from perception.world.scenario import load

SCENARIOS = Path(__file__).resolve().parent.parent / "scenarios"


def _play(scenario, render: bool) -> tuple[float, float, int, float]:
    """Wall time of one demonstration (fresh world), its duration, frames and CPU time."""
    demo = Demonstration(scenario)
    renderer = Renderer(default_cameras(), pixel_noise=scenario.noise.pixel,
                        seed=scenario.seed) if render else None
    t0, c0 = time.perf_counter(), time.process_time()
    for _, scene in demo:
        if renderer is not None:
            renderer.render(scene)
    return (time.perf_counter() - t0, demo.duration, demo.n_frames,
            time.process_time() - c0)


def main(argv: list[str]) -> dict:
    """Print a table per scenario and return the real-time factors."""
    names = argv or sorted(p.stem for p in SCENARIOS.glob("*.yaml"))
    figures: dict = {"fps": 30, "scenarios": {}}
    total = {"sim": 0.0, "both": 0.0, "demo": 0.0, "sim_cpu": 0.0, "both_cpu": 0.0}
    print(f"{'scenario':<16} {'demo s':>7} {'frames':>7} {'sim x':>8} {'sim+render x':>13}"
          f" {'us/frame':>9}")
    for name in names:
        sc = load(SCENARIOS / f"{name}.yaml")
        sims = [_play(sc, False) for _ in range(3)]
        runs = [_play(sc, True) for _ in range(3)]
        sim = min(r[0] for r in sims)
        both, duration, frames, _ = min(runs)
        total["sim"] += sim
        total["both"] += both
        total["demo"] += duration
        total["sim_cpu"] += min(r[3] for r in sims)
        total["both_cpu"] += min(r[3] for r in runs)
        row = {"duration_s": round(duration, 2), "frames": frames,
               "sim_realtime_factor": round(duration / sim, 1),
               "sim_render_realtime_factor": round(duration / both, 1),
               "us_per_frame_sim_render": round(both / frames * 1e6, 1)}
        figures["scenarios"][name] = row
        print(f"{name:<16} {duration:7.1f} {frames:7d} {row['sim_realtime_factor']:8.1f} "
              f"{row['sim_render_realtime_factor']:13.1f} {row['us_per_frame_sim_render']:9.1f}")
    figures["sim_realtime_factor"] = round(total["demo"] / total["sim"], 1)
    figures["sim_render_realtime_factor"] = round(total["demo"] / total["both"], 1)
    figures["sim_realtime_factor_cpu"] = round(total["demo"] / total["sim_cpu"], 1)
    figures["sim_render_realtime_factor_cpu"] = round(total["demo"] / total["both_cpu"], 1)
    print(f"{'all':<16} {total['demo']:7.1f} {'':>7} {figures['sim_realtime_factor']:8.1f} "
          f"{figures['sim_render_realtime_factor']:13.1f}   (target >= 200x together)")
    print(f"{'all, CPU time':<16} {total['demo']:7.1f} {'':>7} "
          f"{figures['sim_realtime_factor_cpu']:8.1f} "
          f"{figures['sim_render_realtime_factor_cpu']:13.1f}")
    return figures


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
