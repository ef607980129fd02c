"""Monitor display (Fig. 19): windows, attention stack and operation drawn on every frame."""

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from lbw_engine.do import plan as planmod
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.pipeline.watch import watch
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from perception.pictures.overlay import (
    ATTN_COLOR,
    HAND_COLOR,
    PANEL_H,
    ExecutionRecorder,
    draw_monitor,
    record_demonstration,
)
from perception.world.generator import generate
from perception.world.scenario import load

ROOT = Path(__file__).resolve().parents[2]


def test_draw_monitor_puts_windows_on_their_view():
    top = np.zeros((256, 256), np.uint8)
    side = np.zeros((256, 256), np.uint8)
    img = draw_monitor(top, side, [("top", (10, 20, 40, 60), "hand"),
                                   ("side", (100, 100, 120, 130), "attention")],
                       ["ATTN level 0: :near hand>b1"], "Task > Transfer", 1.5, scale=2)
    assert img.shape == (512 + PANEL_H, 2 * 512 + 4, 3)
    assert tuple(img[40, 30]) == HAND_COLOR  # top edge of the hand window, scaled 2x
    assert tuple(img[200, 512 + 4 + 210]) == ATTN_COLOR  # the side view is the right tile
    assert tuple(img[200, 210]) != ATTN_COLOR  # ... and not drawn on the top view
    assert img[512:].max() > 200  # the text panel has text


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A generated tower watched through the monitor, with an MP4."""
    sc = generate(5, structures=["tower"]).scenario()
    video = tmp_path_factory.mktemp("video") / "demo.mp4"
    rec, hand, kept = record_demonstration(sc, load_rules(), video, keep_every=1.0, scale=1)
    return sc, rec, hand, kept, video


def test_monitor_does_not_change_recognition(recorded):
    sc, rec, *_ = recorded
    plain, _ = watch(sc, load_rules())
    assert to_actions(rec)["operations"] == to_actions(plain)["operations"]


def test_video_has_one_frame_per_recognized_frame(recorded):
    sc, rec, hand, kept, video = recorded
    cap = cv2.VideoCapture(str(video))
    n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
    ok, first = cap.read()
    cap.release()
    assert ok and first.shape == (256 + PANEL_H, 2 * 256 + 4, 3)
    assert n == len(hand.sight.pixels) + 1  # pixel counts close every frame but the last
    assert len(kept) == pytest.approx(n / 30.0, abs=2)


def test_hand_windows_drawn_while_tracking(recorded):
    *_, kept, _ = recorded
    greens = [(img[:256] == HAND_COLOR).all(axis=2).sum() for _, img in kept]
    assert max(greens) > 50  # the tracker's windows show while the hand is in view
    assert greens[0] == 0  # ... and not before the hand has come in (t = 0)


def test_execution_recorder_renders_the_robot(tmp_path):
    sc = load(ROOT / "scenarios" / "inverted-arch.yaml")
    plan = planmod.parse(json.loads((ROOT / "tests/data/inverted-arch.plan.json").read_text()),
                         file="plan.json")
    recorder = ExecutionRecorder(tmp_path / "exec.mp4", every=3, keep_every=5.0, scale=1)
    result = execute_plan(plan, sc, load_rules(), on_step=recorder)
    recorder.close()
    assert result.success
    cap = cv2.VideoCapture(str(tmp_path / "exec.mp4"))
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == recorder.steps // 3
    cap.release()
    first, last = recorder.kept[0][1], recorder.kept[-1][1]
    assert np.abs(first.astype(int) - last.astype(int)).mean() > 1.0  # the scene changed
