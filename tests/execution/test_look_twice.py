"""Readings the monitor must not take for faults (stop 32).

At pixel noise 8 one image in many misreads a stack; the monitor took that reading for
the workspace, traced its repair from it and then failed the final verdict on a
structure that was right. A real difference is in both images.
"""

import json
from pathlib import Path

from lbw_engine.cli import main
from lbw_engine.do.verification import ObjectState, verify
from lbw_engine.pipeline.monitor import Look, look_twice

DATA = Path(__file__).resolve().parent / "data"
EXPECTED = {"c": (0.0, 200.0, 15.0)}
SUPPORTS = {"c": ("on", ("table",))}


class _Eyes:
    """Looks that return the given readings of cube c, one per call."""

    def __init__(self, *zs: float) -> None:
        self.zs = list(zs)
        self.calls = 0
        self.windows, self.last_images = [], None  # what the pictures draw of a look

    def look(self, expected):
        self.calls += 1
        z = self.zs.pop(0)
        self.windows, self.last_images = [("top", self.calls)], {"look": self.calls}
        return Look({"c": ObjectState((0.0, 200.0, z), (30.0, 30.0, 30.0))}, [], [])


def _check(states):
    return verify(EXPECTED, SUPPORTS, states, ("on",))


def test_a_misreading_in_one_image_is_not_a_difference():
    eyes = _Eyes(31.0, 15.2)  # read 16 mm too high once
    seen, verdict = look_twice(eyes, EXPECTED, _check)
    assert verdict.success and eyes.calls == 2
    assert seen.states["c"].position[2] == 15.2


def test_a_difference_seen_twice_stands():
    eyes = _Eyes(45.0, 45.5)
    seen, verdict = look_twice(eyes, EXPECTED, _check)
    assert not verdict.success and eyes.calls == 2
    assert seen.states["c"].position[2] == 45.0  # the first reading is kept
    assert eyes.windows == [("top", 1)] and eyes.last_images == {"look": 1}  # and drawn


def test_an_agreeing_look_is_taken_once():
    eyes = _Eyes(15.0)
    assert look_twice(eyes, EXPECTED, _check)[1].success and eyes.calls == 1


def test_a_base_moved_with_its_rider_at_4x_is_done_and_verified(tmp_path, capsys):
    """Generated rearrange 3107 at 4x. The base taught carrying an equal cube was matched
    to an uncovered cube (first come, first served); matched to the cube carrying one, the
    run's last look read the 50 mm block under a cube as a 21 mm slice, and the repair
    traced from it failed the final verdict."""
    out = tmp_path / "run"
    assert main(["run", str(DATA / "base-and-rider-4x.yaml"), "--out", str(out)]) == 0, \
        capsys.readouterr().err
    report = json.loads((out / "execution.json").read_text())
    assert report["verification"] == {"cameras": True, "ground_truth": True}
    assert report["initial_state"]["matching"]["a-base"][2] < 30  # the lower cube
    assert report["monitor"]["detections"] == []

