"""The recognizer gets frames only: it runs where the simulator cannot even be imported."""

from __future__ import annotations

import subprocess
import sys
from itertools import islice

import numpy as np

from perception.vision.camera import default_cameras
from perception.world.scenario import load
from perception.world.stream import demonstration_frames, teach_names

from .conftest import ROOT

SECONDS = 15.0  # place-and-align: REACH and PICK of block1 are over by then

CHILD = r"""
import sys
for name in ("pymunk", "perception.world"):
    sys.modules[name] = None  # any import of the simulator now fails
import json
import numpy as np
from lbw_engine.see.actions import to_actions
from lbw_engine.rules import load_rules
from perception.vision.camera import default_cameras
from perception.vision.envnodes.registry import watch_frames
from perception.vision.frames import Frame
data = np.load(sys.argv[1])
hint = json.loads(sys.argv[2])
frames = [Frame(i, float(t), top, side)
          for i, (t, top, side) in enumerate(zip(data["t"], data["top"], data["side"]))]
shapes = {"block": [40.0, 30.0, 50.0]}
rec, _ = watch_frames(frames, default_cameras(), shapes, load_rules(),
                      {k: (v[0], tuple(v[1])) for k, v in hint.items()})
print(json.dumps([op["operation"] for op in to_actions(rec)["operations"]]))
"""


def test_recognizer_runs_on_a_plain_list_of_frames_without_the_simulator(tmp_path):
    sc = load(ROOT / "scenarios" / "place-and-align.yaml")
    frames = list(islice(demonstration_frames(sc, default_cameras()), int(SECONDS * 30)))
    path = tmp_path / "frames.npz"
    np.savez(path, t=np.array([f.t for f in frames]),
             top=np.stack([f.top for f in frames]), side=np.stack([f.side for f in frames]))
    import json
    hint = json.dumps({k: [s, list(p)] for k, (s, p) in teach_names(sc).items()})
    out = subprocess.run([sys.executable, "-c", CHILD, str(path), hint], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    ops = json.loads(out.stdout.strip().splitlines()[-1])
    assert ops[:2] == ["REACH", "PICK"]
