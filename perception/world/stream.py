"""Frame sources from the simulated workspace: demonstrator -> renderer -> Frames.

This is the world side (it imports the demonstrator and the renderer); the
recognizer only ever receives the iterator of ``Frame`` it produces
(docs/architecture.md, docs/seeing.md).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from perception.vision.camera import Camera, default_cameras
from perception.vision.frames import Frame
from perception.world.demonstrator import Demonstration
from perception.world.render import Renderer


def demonstration_frames(scenario, cameras: Mapping[str, Camera] | None = None,
                         fps: float = 30.0, pixel_noise: float | None = None,
                         demonstration: Demonstration | None = None) -> Iterator[Frame]:
    """Render each frame of the scenario's demonstration as it is simulated (online)."""
    cams = dict(cameras or default_cameras())
    noise = scenario.noise.pixel if pixel_noise is None else pixel_noise
    renderer = Renderer(cams, pixel_noise=noise, seed=scenario.seed)
    demo = demonstration or Demonstration(scenario, fps=fps)
    for index, (t, scene) in enumerate(demo):
        views = renderer.render(scene)
        yield Frame(index, t, views["top"], views["side"])


def teach_names(scenario) -> dict[str, tuple[str, tuple[float, float, float]]]:
    """Naming hint: teach object name -> (shape, centre x y z) (the paper's manual shape
    names). The height tells apart blocks of one shape stacked on each other."""
    return {name: (spec.shape, tuple(float(c) for c in spec.center))
            for name, spec in scenario.teach.objects.items()}
