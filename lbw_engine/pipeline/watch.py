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


def slide_notes(scenario: Any, rules: Any) -> list[str]:
    """One line per ``align`` step whose slide the eye may not read as the scenario says
    (rules/constants.yaml ``align-slide``, ``align-slide-doubt``): one shorter than
    align-slide cannot be told from a place already in line, so it is not learned as a
    slide (helper round 16: a 2-3 mm slide went unlearned without a word); one within
    align-slide-doubt of it may be learned either way."""
    from perception.world.layout import slide_mm, slide_reading

    least = float(rules.constants["align-slide"])
    doubt = float(rules.constants["align-slide-doubt"])
    out = []
    for step in scenario.demonstration:
        mm = slide_mm(step)
        if mm is None:
            continue
        where = f"line {step.line}: " if step.line else ""
        must, may = slide_reading(step, least, doubt)
        if must != may:
            out.append(f"note: {where}the align of '{step.obj}' slides it {mm:.1f} mm, within "
                       f"{doubt:g} mm of align-slide ({least:g} mm in constants.yaml, "
                       "align-slide-doubt): it may be learned as a slide or as a place "
                       "already in line, and either counts as seen right")
        elif mm < least:
            out.append(f"note: {where}the align of '{step.obj}' slides it {mm:.1f} mm, under "
                       f"align-slide ({least:g} mm in constants.yaml): so short a slide "
                       "cannot be told from a place already in line and is not learned as one")
    return out
