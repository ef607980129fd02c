"""``lbw render SCENARIO --out DIR``: the demonstration as a video (both camera views)."""

from __future__ import annotations

import argparse
from pathlib import Path

from lbw_engine.errors import InputError
from lbw_engine.guard import MAX_FPS, Place, number
from lbw_engine.outputs import OutputDir

HELP = "render a scenario's demonstration to DIR/demonstration.mp4 (top | side views)"
EXIT_CODES = ("0 the video is written; 2 bad input (one line: file, place, what is wrong); "
              "3 internal error")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """SCENARIO file, --out DIR, optional --fps and --size."""
    parser.add_argument("scenario", metavar="SCENARIO", help="scenario YAML file")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument("--fps", type=float, metavar="N", default=30.0,
                        help="frames per second (30)")
    parser.add_argument("--size", type=int, metavar="N", default=256,
                        help="camera image size in pixels (256)")


def run(args: argparse.Namespace) -> int:
    """Simulate the demonstration, render every frame, write an MP4 (published on success)."""
    import numpy as np

    from perception.pictures.video import VideoFile
    from perception.vision.camera import default_cameras
    from perception.world.demonstrator import Demonstration
    from perception.world.render import Renderer
    from perception.world.scenario import load

    number(args.fps, Place(where="--fps"), 0, MAX_FPS, above=True, unit="frames per second")
    if not 16 <= args.size <= 4096:
        raise InputError(f"expected 16-4096 pixels, got {args.size}", where="--size")
    scenario = load(Path(args.scenario))
    demo = Demonstration(scenario, fps=args.fps)
    renderer = Renderer(default_cameras(args.size), pixel_noise=scenario.noise.pixel,
                        seed=scenario.seed)
    with OutputDir(args.out, inputs=[args.scenario]) as out:
        video = VideoFile(out.path("demonstration.mp4"), args.fps)  # H.264: browsers play it
        try:
            for _, scene in demo:
                views = renderer.render(scene)
                video.add(np.hstack([views["top"], views["side"]]))
        finally:
            video.close()
    print(f"lbw render: {demo.n_frames} frames ({demo.duration:.1f} s) -> "
          f"{Path(args.out) / 'demonstration.mp4'}")
    return 0
