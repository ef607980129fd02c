"""The interpreter beyond the tables: FineMotion ALIGN (Fig. 11), env-model
updates (Sec. V-B4), end of input, and the detector registry."""

import pytest

from lbw_engine.errors import InputError
from lbw_engine.model.env import EnvModel
from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.see.detectors import Detection, DetectorRegistry
from lbw_engine.see.recognizer import Recognizer
from lbw_engine.see.replay import run_script

RULES = load_rules()
B = {"shape": "brick", "size": [30, 30, 50]}
LOCATE = [{"event": "loc-exist", "found": ["b1", "b2"], "objects": {
    "b1": {**B, "position": [0, 200, 25]}, "b2": {**B, "position": [100, 200, 25]}}}]
ENTER = [{"event": "found-moving", "found": ["hand"], "positions": {"hand": [0, 300, 200]}}]
DOWN = [{"event": "small-motion", "value": "moving-down"}]
PICK_B1 = [DOWN, [{"event": "near", "found": ["b1"]}],
           [{"event": "far", "positions": {"hand": [0, 200, 150]}},
            {"detector": "change-detector", "value": "decreased", "at": [0, 200, 25]}]]
PLACE_ON_B2_ALIGNED = [
    DOWN, [{"event": "near", "found": ["b2"]}], [{"event": "join"}],
    [{"event": "split"}, {"detector": "coplanar-detector", "value": "positive"}],
    [{"event": "far"}, {"detector": "change-detector", "value": "increased", "at": [98, 203, 70]}],
]


def test_align_during_a_place():
    rec = run_script(RULES, [LOCATE, ENTER, *PICK_B1, *PLACE_ON_B2_ALIGNED])
    place = rec.root.history[-1]
    assert place.operation == "PLACE-ON-BLOCK"
    assert [(n.motion, n.operation) for n in place.history] == [
        ("Approach", "APPROACH-WITH-OBJ"), ("FineMotion", "ALIGN"), ("Depart", "DEPART-WITH-OBJ")]
    assert [f["operation"] for f in to_actions(rec)["operations"][-1]["fine"]] == ["ALIGN"]
    fine = place.history[1]
    assert (fine.base, fine.target) == (("b1",), ("b2",))  # the held block meets the target
    assert ["coplanar", "b1", "b2"] in [r.to_json() for r in rec.env.relations]


def test_place_recomputes_height_from_supports():
    """The change-detector measured z = 70; the model puts b1 on b2's top: 50 + 25."""
    rec = run_script(RULES, [LOCATE, ENTER, *PICK_B1, *PLACE_ON_B2_ALIGNED])
    assert rec.env.nodes["b1"].position == (98.0, 203.0, 75.0)
    on = [r for r in rec.env.relations if r.subject == "b1" and r.type == "on"]
    assert [(r.obj, r.at, r.wrt) for r in on] == [("b2", (-2.0, 3.0, 50.0), "b2")]


def test_held_block_follows_the_hand():
    rec = run_script(RULES, [LOCATE, ENTER, *PICK_B1, [{
        "event": "small-motion", "value": "moving-laterally",
        "positions": {"hand": [50, 250, 160]}}]])
    assert rec.env.held() == ("b1",)
    assert rec.env.nodes["b1"].position == (50.0, 250.0, 35.0)  # offset kept: 25 - 150 + 160


def test_end_of_input_closes_open_motions():
    rec = run_script(RULES, [LOCATE, ENTER, DOWN])
    rec.finish()
    ops = to_actions(rec)["operations"]
    assert [(o["operation"], o["final_event"]) for o in ops] == [("WITHDRAW", None)]
    assert rec.finished and rec.stack.describe() == []


def test_registry_needs_every_detector_the_rules_name():
    with pytest.raises(InputError, match="has no implementation"):
        DetectorRegistry.for_rules(RULES, {})


class Scripted:
    """A detector double that answers one event once, from a velocity (Table IV path)."""

    def __init__(self):
        self.frames = []

    def begin_frame(self, t, frame):
        self.frames.append((t, frame))

    def query(self, query, env):
        if query.event == RULES.transitions[("Task", "loc-exist")].key:
            return Detection(found=(), objects={})
        return None

    def snapshot(self, act, env):
        return None

    def compare(self, first, last, act, env):
        return None


def test_frames_reach_every_detector_once_per_frame():
    double = Scripted()
    provided = {name: double for name, d in RULES.detectors.items() if not d.builtin}
    rec = Recognizer(RULES, DetectorRegistry.for_rules(RULES, provided), EnvModel(RULES))
    rec.run([(0.0, "frame0"), (0.1, "frame1")])
    assert double.frames == [(0.0, "frame0"), (0.1, "frame1")]


def _deferred_place(pending_until: float, judged_at: int):
    """Pick b1, put it on b2 (its :Far at frame 8), reach for b1 again (:Near at frame 11),
    with the change-detector unable to judge the place's end before ``pending_until``;
    its comparison is recorded on frame ``judged_at``."""
    from lbw_engine.see.replay import replay_detectors, script_trace

    place = [DOWN, [{"event": "near", "found": ["b2"]}], [{"event": "far"}]]
    frames = [LOCATE, ENTER, *PICK_B1, *place, [], DOWN, [{"event": "near", "found": ["b1"]}]]
    judged = {"detector": "change-detector", "value": "increased", "at": [100, 200, 75]}
    frames[judged_at - 1] = [*frames[judged_at - 1], judged]
    detectors = replay_detectors(script_trace(RULES, frames), RULES)
    # a replay snapshot is the time it was taken: the place's end cannot be judged before
    detectors["change-detector"].pending = lambda last: 8 <= last < pending_until
    rec = Recognizer(RULES, DetectorRegistry.for_rules(RULES, detectors))
    for t in range(len(frames) + 1):
        rec.step(float(t))
    return rec


@pytest.mark.parametrize("pending_until, judged_at", [(10, 10), (99, 11)],
                         ids=["judged-once-clear", "forced-by-the-next-motion"])
def test_a_motion_judged_late_rebinds_the_one_after_it(pending_until, judged_at):
    """A place whose end the detector cannot judge yet (the hand hides it) is classified
    later, at the latest when the motion after it ends, and before it; the Transfer begun
    in between was bound while the env model still had b1 in the hand: it is bound again
    (no special) and classified a REACH, not a REACH-WITH-OBJ; its target, closed at its
    :Near, stays (lbw bench 1264)."""
    rec = _deferred_place(pending_until, judged_at)
    place, reach = rec.root.history[-2:]
    assert (place.operation, place.special, place.target) == ("PLACE-ON-BLOCK", ("b1",), ("b2",))
    assert (reach.operation, reach.special) == ("REACH", ())
    assert reach.target == ("b1",)  # closed to what its :Near found, not bound again
    assert not rec.deferred and rec.env.held() == ()
    assert ("holding", "hand", "b1") not in {tuple(r.to_json()[:3])
                                             for r in reach.initial_state.relations}
