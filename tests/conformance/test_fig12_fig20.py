"""Fig. 12 and Fig. 20 sequences from replayed event traces, and the Fig. 21 final
state of the last PLACE of Build Table (on-multiple, co-support with :at :wrt).

How the sequences end (docs/decisions.md): in Fig. 12 the last PLACE ends by
:Far, the Transfer that follows is cut by :Found-moving (Sec. V-A Case 2:
WITHDRAW) and the next one by :Disappeared (:up, WITHDRAW); in Fig. 20 the
last PLACE ends by :Found-moving (Fig. 21's final-event) and the last
Transfer by :Disappeared.
"""

from pathlib import Path

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.actions import to_actions
from lbw_engine.see.replay import recognize_trace

TRACES = Path(__file__).resolve().parent.parent / "data" / "traces"
RULES = load_rules()
FIG12 = ("reach01 pick01 reach-with-obj01 place-on-table01 reach02 pick02 reach-with-obj02 "
         "place-on-block01 reach03 no01 reach04 pick03 reach-with-obj03 place-on-block02 reach05 "
         "pick04 reach-with-obj04 place-on-block03 withdraw01 withdraw02").split()
FIG20 = ("reach pick reach-with-obj place-on-table " * 4
         + "reach pick reach-with-obj place-on-block withdraw").split()


def actions(name):
    rec, trace = recognize_trace(TRACES / name, RULES)
    assert trace.unused() == []  # every record answered a query the rules made
    return to_actions(rec)


def test_fig12_sequence():
    ops = actions("fig12-inverted-arch.jsonl")["operations"]
    assert [op["name"] for op in ops] == FIG12
    assert [op["final_event"] for op in ops[-3:]] == ["far", "found-moving", "disappeared"]


def test_fig20_sequence():
    ops = actions("fig20-build-table.jsonl")["operations"]
    assert len(ops) == 21
    assert [op["operation"].lower() for op in ops] == FIG20


@pytest.fixture(scope="module")
def last_place():
    return actions("fig20-build-table.jsonl")["operations"][-2]


LEGS = {  # Fig. 21: leg positions and the co-support :at relative to the plate
    "brick190": ([-24.9, 178.9, 25.0], [0.2, 27.9, -34.8]),
    "brick186": ([12.5, 126.9, 25.0], [37.6, -24.1, -34.8]),
    "brick187": ([-73.1, 137.3, 25.0], [-48.0, -13.7, -34.8]),
    "brick188": ([-42.9, 85.7, 25.0], [-17.8, -65.3, -34.8]),
}


def test_fig21_slots(last_place):
    assert last_place["operation"] == "PLACE-ON-BLOCK"
    assert (last_place["initial_event"], last_place["final_event"]) == ("near", "found-moving")
    assert last_place["base"] == ["hand"] and last_place["special"] == ["plate189"]
    assert sorted(last_place["target"]) == sorted(LEGS)


def test_fig21_initial_state(last_place):
    rels = last_place["initial_state"]["relations"]
    assert ["holding", "hand", "plate189"] in rels
    assert ["held-by", "plate189", "hand"] in rels
    for leg, (pos, _) in LEGS.items():
        assert ["on", leg, "table", {"at": pos, "wrt": "table"}] in rels


def test_fig21_final_state(last_place):
    final = last_place["final_state"]
    rels = final["relations"]
    assert not any(r[0] in ("holding", "held-by") for r in rels)
    multiple = [r for r in rels if r[0] == "on-multiple"]
    assert len(multiple) == 1
    _, subject, supports, at = multiple[0]
    assert subject == "plate189" and sorted(supports) == sorted(LEGS)
    assert at == {"at": [-25.1, 151.0, 59.8], "wrt": "table"}  # height from the legs' tops
    for leg, (pos, rel) in LEGS.items():
        assert ["co-support", leg, "plate189", {"at": rel, "wrt": "plate189"}] in rels
        assert ["on", leg, "table", {"at": pos, "wrt": "table"}] in rels
    assert final["positions"]["plate189"] == [-25.1, 151.0, 59.8]


def test_objects_are_the_initial_state():
    objects = actions("fig20-build-table.jsonl")["objects"]
    assert set(objects) == {*LEGS, "plate189"}
    assert objects["plate189"] == {"shape": "plate", "position": [180.0, 250.0, 9.8]}


def test_fig14_plank_carries_its_bricks():
    """Fig. 12's last PLACE puts the plank, with two bricks on it, on the pillar."""
    ops = actions("fig12-inverted-arch.jsonl")["operations"]
    place = ops[17]
    assert (place["operation"], place["special"], place["target"]) == (
        "PLACE-ON-BLOCK", ["planar-brick2"], ["short-brick1"])
    final = {r[1]: r for r in place["final_state"]["relations"]}
    on = final["planar-brick2"]
    assert on[:3] == ["on", "planar-brick2", "short-brick1"] and on[3]["wrt"] == "short-brick1"
    assert on[3]["at"][2] == 30.0  # half the pillar (25) + half the plank (5)
    rec, _ = recognize_trace(TRACES / "fig12-inverted-arch.jsonl", RULES)
    for rider in ("medium-brick3", "medium-brick4"):  # they rode along: 50 + 10 + 70/2
        assert rec.env.nodes[rider].position[2] == pytest.approx(95.0)
        assert rec.env.supports_of(rider) == ["planar-brick2"]
