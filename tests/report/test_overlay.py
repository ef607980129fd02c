"""Monitor display (Fig. 19) and the videos: windows, stack and operation on every frame;
H.264 files that browsers play; the execution filmed in real time."""

import json
import re
import subprocess

import cv2
import imageio_ffmpeg
import numpy as np
import pytest

from lbw_engine.pipeline.watch import watch
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from perception.pictures.overlay import (
    ATTN_COLOR,
    HAND_COLOR,
    PANEL_H,
    ExecutionRecorder,
    draw_monitor,
)
from perception.pictures.video import VideoFile
from perception.world.physics import World
from perception.world.scenario import load

from .conftest import RecordedRun


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


def _probe(path) -> str:
    """ffmpeg's description of a file (its stderr)."""
    return subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i", str(path)],
                          capture_output=True, text=True).stderr


def _frames(path, every: int = 1) -> list[np.ndarray]:
    """Every ``every``-th decoded frame of a video."""
    cap, out, i = cv2.VideoCapture(str(path)), [], 0
    while True:
        ok, frame = cap.read()
        if not ok:
            break
        if i % every == 0:
            out.append(frame)
        i += 1
    cap.release()
    return out


def test_video_file_is_h264_padded_to_whole_macroblocks(tmp_path):
    video = VideoFile(tmp_path / "v.mp4", fps=10)
    images = []
    for k in range(5):  # odd sizes; a white square moving right, frame by frame
        image = np.full((50, 70, 3), 60, np.uint8)
        image[10:30, 10 * k:10 * k + 20] = 255
        images.append(image)
        video.add(image)
    video.close()
    assert video.frames == 5 and video.size == (80, 64)
    assert re.search(r"Video: h264 .*yuv420p.*80x64", _probe(tmp_path / "v.mp4"))
    decoded = _frames(tmp_path / "v.mp4")
    assert len(decoded) == 5
    for k, frame in enumerate(decoded):
        errors = [np.abs(frame[:48, :64].astype(int) - image[:48, :64]).mean()
                  for image in images]
        assert np.argmin(errors) == k and errors[k] < 4  # each picture kept, in order
        assert frame[54:, 74:].max() < 20  # the padding is black


def test_video_file_without_a_path_writes_nothing(tmp_path):
    video = VideoFile(None, fps=10)
    video.add(np.zeros((16, 16, 3), np.uint8))
    video.close()
    assert video.frames == 0 and list(tmp_path.iterdir()) == []


@pytest.mark.heavy
def test_monitor_does_not_change_recognition(recorded_run: RecordedRun):
    """The run watched through the monitor and the motion recorder; a plain watch agrees."""
    plain, _ = watch(load(recorded_run.scenario), load_rules())
    ops = json.loads(json.dumps(to_actions(plain)["operations"]))
    assert recorded_run.json("actions.json")["operations"] == ops


def test_hand_windows_drawn_while_tracking(recorded_run: RecordedRun):
    frames = _frames(recorded_run.out / "demonstration.mp4", every=30)
    views = [f[:256].astype(int) for f in frames]  # the run is recorded at scale 1
    # the hand-tracker's windows are pure green, the scene gray (4:2:0 chroma blurs the
    # 1-px lines: green stands out by 50 gray levels, not the 160 drawn)
    greens = [int(((v[..., 1] - np.maximum(v[..., 0], v[..., 2])) > 50).sum()) for v in views]
    assert max(greens) > 50  # the tracker's windows show while the hand is in view
    assert greens[0] == 0  # ... and not before the hand has come in (t = 0)


def test_execution_recorder_films_in_real_time(tmp_path):
    """Robot steps of 1/60 s, filmed at 30 frames per second of robot time."""
    world = World([])
    recorder = ExecutionRecorder(tmp_path / "exec.mp4", fps=30, keep_every=0.5, scale=1)
    for _ in range(120):  # 2 s of robot time
        world.step(1 / 60)
        recorder(world)
    recorder.close()
    assert recorder.steps == 120 and recorder.rendered == 60
    assert len(_frames(tmp_path / "exec.mp4")) == 60
    assert [round(t, 2) for t, _ in recorder.kept] == [0.02, 0.52, 1.02, 1.52]
    assert "30 fps" in _probe(tmp_path / "exec.mp4")


@pytest.mark.parametrize("fps,frames", [(30, 60), (10, 20), (60, 120)])
def test_execution_recorder_frame_rate(fps, frames):
    world = World([])
    recorder = ExecutionRecorder(None, fps=fps, scale=1)
    for _ in range(120):
        world.step(1 / 60)
        recorder(world)
    assert recorder.rendered == frames


def test_execution_panel_prints_detections_in_whole_mm():
    """Helper round 21: a detection's numpy floats showed as np.float64(29.2) on the video."""
    from types import SimpleNamespace

    rec = ExecutionRecorder.__new__(ExecutionRecorder)
    det = {"object": "s", "kind": "position", "operator": "achieve01",
           "expected": [np.float64(0.4), 190.0, 10.0], "observed": [np.float64(29.2), 190.1, 9.6]}
    rec.monitor = SimpleNamespace(detections=[det], repairs=[], current="achieve01")
    rec.robot = SimpleNamespace(current=None)
    rec.eyes = SimpleNamespace(windows=[])
    _, lines, _ = rec._panel()
    assert lines == ["detected: s (position) after achieve01, expected [0, 190, 10], "
                     "seen [29, 190, 10]"]
