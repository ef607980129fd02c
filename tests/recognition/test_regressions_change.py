"""Change-detector (SilDiff) regressions on generated scenarios (`lbw bench`, 4x noise).

Seed 1077 at 4x: the hand touches a lone block and rises straight up; at the end of
the LocalMotion the palm hides the block in the top view and the holder window
between the fingers, looking down, reads "holding" (0.68) off the block below. The
side view still shows the block in place with nothing else on its line of sight, so
the touch must stay a NO-OP (it was a PICK, and the block then counted as held).
"""

from __future__ import annotations

from lbw_engine.actions import to_actions
from lbw_engine.rules import load_rules
from perception.camera import default_cameras
from perception.envnodes_adapters import watch_frames
from perception.generator import generate
from perception.groundtruth import expected_operations
from perception.stream import demonstration_frames, teach_names


def test_touch_seen_in_place_by_the_side_view_is_not_a_pick():
    sc = generate(1077, "4x").scenario()
    cams = default_cameras()
    rec, _ = watch_frames(demonstration_frames(sc, cams), cams, sc.shapes, load_rules(),
                          teach_names(sc))
    ops = [op["operation"] for op in to_actions(rec)["operations"]]
    assert ops == expected_operations(sc)
    touched = {step.obj for step in sc.demonstration if step.kind == "touch"}
    assert touched and not touched & set(rec.env.held())
    for name in touched:  # a touched block stays on what it stood on
        assert set(rec.env.supports_of(name)) == set(sc.states[-1].support[name])
