"""Seeing (Sec. III-V): the demonstration, rendered frame by frame, recognized online.

The world side (demonstrator and renderer, ``perception.world.stream``)
produces frames one at a time; the recognizer
(``perception.vision.envnodes.registry.watch_frames``) receives only that frame
iterator, the camera models, the shape database and the teach names as a
naming hint (docs/seeing.md).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def watch(scenario: Any, rules: Any, fps: float = 30.0, pixel_noise: float | None = None,
          on_frame: Callable[..., None] | None = None) -> tuple[Any, Any]:
    """Simulate, render and recognize online; returns (recognizer, hand state).

    ``on_frame(frame, recognizer, hand)`` runs after each frame (the monitor display)."""
    from perception.vision.camera import default_cameras
    from perception.vision.envnodes.registry import watch_frames
    from perception.world.stream import demonstration_frames, teach_names

    cameras = default_cameras()
    frames = demonstration_frames(scenario, cameras, fps=fps, pixel_noise=pixel_noise)
    return watch_frames(frames, cameras, scenario.shapes, rules, teach_names(scenario),
                        on_frame)


def repair(actions: dict[str, Any], rules: Any) -> Any:
    """Recognition repair (Sec. IX-C2, lbw_engine.understand.repair) of a recognized
    sequence; one the analysis could not read either (an unclassified motion) is left
    as it is, unchecked."""
    from lbw_engine.errors import InputError
    from lbw_engine.understand import RelationTable, parse_actions
    from lbw_engine.understand.repair import Repaired, repair_actions

    try:
        parse_actions(actions, RelationTable(rules.analysis.tolerance), file="actions.json")
    except InputError as exc:
        return Repaired(actions, left=[str(exc)], checked=False)
    return repair_actions(actions, rules)
