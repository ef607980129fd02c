"""Watching a bench scenario (perception.world.generator) and checking it against the ground truth.

Shared by the regression files of this folder: each names the seeds (and noise
levels) of `lbw bench` that once failed and the cause that was fixed.
"""

from __future__ import annotations

from typing import Any

from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from perception.vision.camera import default_cameras
from perception.vision.envnodes.registry import watch_frames
from perception.world.generator import generate
from perception.world.groundtruth import expected_operations
from perception.world.stream import demonstration_frames, teach_names

RULES = load_rules()


def watch_generated(seed: int, level: str = "nominal", family: str = "classic"
                    ) -> tuple[Any, Any, dict[str, Any]]:
    """(scenario, recognizer, actions.json content) of one generated demonstration."""
    sc = generate(seed, level, family=family).scenario()
    cams = default_cameras()
    rec, _ = watch_frames(demonstration_frames(sc, cams), cams, sc.shapes, load_rules(),
                          teach_names(sc))
    return sc, rec, to_actions(rec)


def watch_file(path: Any) -> tuple[Any, Any, dict[str, Any]]:
    """(scenario, recognizer, actions.json content) of a scenario file's demonstration."""
    from perception.world.scenario import load

    sc = load(path)
    cams = default_cameras()
    rec, _ = watch_frames(demonstration_frames(sc, cams), cams, sc.shapes, RULES,
                          teach_names(sc))
    return sc, rec, to_actions(rec)


def assert_sequence(sc: Any, actions: dict[str, Any]) -> None:
    """The recognized top-level sequence is the demonstrator's."""
    assert [op["operation"] for op in actions["operations"]] == expected_operations(sc, RULES)


def assert_supports(sc: Any, rec: Any) -> None:
    """Every moved object ends, in the env model, on what it really rests on."""
    final = sc.states[-1]
    moved = {step.obj for step in sc.demonstration if step.kind in ("pick", "place")}
    recognized = {name: set(rec.env.supports_of(name)) for name in moved}
    assert recognized == {name: set(final.support[name]) for name in moved}


def assert_targets(sc: Any, actions: dict[str, Any]) -> None:
    """Every recognized operation acts on the objects the demonstrator's did (the bench's
    targets column, lbw_engine.cli.benchscore.target_difference)."""
    from lbw_engine.cli.benchscore import target_difference
    from perception.world.groundtruth import ground_truth

    assert target_difference(ground_truth(sc, RULES), actions["operations"], {}) is None

