"""Watch benchmark (issue #5): real-time factor, pixels read, and memory vs demonstration length.

1. ``lbw watch`` on build-table at 30 fps in one process: demonstrated seconds per
   wall second, end to end (simulation + rendering + recognition) and for the
   recognizer alone (wall time minus the time spent producing frames). Target >= 50.
   Also the end-to-end factor in CPU seconds of the process (robust to other load).
2. Pixels the detectors read per frame (the resource manager's count), averaged,
   as a fraction of the two full frames. Target <= 10 %.
3. Peak resident memory of a normal and a 10x longer demonstration (the same
   pick-and-place repeated), each in a fresh process. It must not grow.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

LONG = """name: long-watch
seed: 7
shapes:
  brick: [30, 30, 50]
teach:
  objects:
    brick1: {shape: brick, at: [-150, 100]}
    brick2: {shape: brick, at: [150, 300]}
  demonstration:
"""

CHILD = r"""
import json, resource, sys, time
from lbw_engine.rules import load_rules
from lbw_engine.pipeline.watch import watch
from perception.world.scenario import load, load_text
text = sys.argv[1]
sc = load(text) if text.endswith(".yaml") else load_text(text, "<long>")
t0 = time.perf_counter()
rec, hand = watch(sc, load_rules())
wall = time.perf_counter() - t0
ops = [n.operation for n in rec.root.history] if rec.root else []
print(json.dumps({"wall": wall, "demo": rec.t, "ops": len(ops),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def long_scenario(repeats: int) -> str:
    """A scenario whose demonstration moves brick1 back and forth ``repeats`` times."""
    steps = []
    for _ in range(repeats):
        steps += ["    - pick: brick1", "    - place: brick1", "      on: table",
                  "      at: [0, 200]", "    - pick: brick1", "    - place: brick1",
                  "      on: table", "      at: [-150, 100]"]
    return LONG + "\n".join(steps) + "\n"


def _child(arg: str) -> dict:
    """Run one watch in a fresh process; its figures."""
    out = subprocess.run([sys.executable, "-c", CHILD, arg], cwd=ROOT, capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def real_time(name: str = "build-table") -> dict:
    """End-to-end and recognizer-only real-time factors, and the pixel fraction."""
    from lbw_engine.rules import load_rules
    from perception.vision.camera import default_cameras
    from perception.vision.envnodes.registry import watch_frames
    from perception.world.scenario import load
    from perception.world.stream import demonstration_frames, teach_names

    sc = load(ROOT / "scenarios" / f"{name}.yaml")
    cams = default_cameras()
    producing = [0.0]

    def timed(frames):
        it = iter(frames)
        while True:
            t0 = time.perf_counter()
            try:
                f = next(it)
            except StopIteration:
                return
            producing[0] += time.perf_counter() - t0
            yield f

    t0, c0 = time.perf_counter(), time.process_time()
    rec, hand = watch_frames(timed(demonstration_frames(sc, cams)), cams, sc.shapes,
                             load_rules(), teach_names(sc))
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0
    demo = rec.t
    full = 2 * cams["top"].size[0] * cams["top"].size[1]
    return {"demo_s": demo, "wall_s": wall, "rtf_end_to_end": demo / wall,
            "rtf_recognizer": demo / max(1e-9, wall - producing[0]),
            "rtf_end_to_end_cpu": demo / cpu,
            "pixel_fraction": sum(hand.sight.pixels) / len(hand.sight.pixels) / full}


def main(argv: list[str]) -> dict:
    """Print and return the figures."""
    rt = real_time()
    print(f"build-table: {rt['demo_s']:.1f} s demonstrated in {rt['wall_s']:.2f} s wall: "
          f"{rt['rtf_end_to_end']:.0f}x real time end to end, "
          f"{rt['rtf_recognizer']:.0f}x for the recognizer alone; "
          f"{rt['rtf_end_to_end_cpu']:.0f}x end to end in CPU time")
    print(f"pixels read per frame: {100 * rt['pixel_fraction']:.2f} % of the two full frames")
    short = _child(long_scenario(1))
    longer = _child(long_scenario(10))
    print(f"peak memory: {short['peak_mb']:.0f} MB for {short['demo']:.0f} s "
          f"({short['ops']} ops), {longer['peak_mb']:.0f} MB for {longer['demo']:.0f} s "
          f"({longer['ops']} ops)")
    return {"build_table": rt, "memory": {"normal": short, "ten_times": longer,
                                          "growth": longer["peak_mb"] / short["peak_mb"]}}


if __name__ == "__main__":  # pragma: no cover
    main(sys.argv[1:])
