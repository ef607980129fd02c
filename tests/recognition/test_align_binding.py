"""ALIGN's effect names the two blocks whose faces became coplanar (Fig. 5, rules/effects.yaml).

The FineMotion's target is the place's support; the coplanar-detector knows which
neighbour it checked and reports it as ``found``, which the `{found: copl-det}`
binding uses. A replayed trace with no such name falls back to the target.
"""

from __future__ import annotations

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see import replay
from lbw_engine.see.detectors import Detection
from lbw_engine.see.replay import run_script

RULES = load_rules()
B = {"shape": "brick", "size": [30, 30, 50]}
LOCATE = [{"event": "loc-exist", "found": ["b1", "b2", "b3"], "objects": {
    "b1": {**B, "position": [0, 200, 25]}, "b2": {**B, "position": [100, 200, 25]},
    "b3": {**B, "position": [100, 231, 25]}}}]
ENTER = [{"event": "found-moving", "found": ["hand"], "positions": {"hand": [0, 300, 200]}}]
DOWN = [{"event": "small-motion", "value": "moving-down"}]
PICK_B1 = [DOWN, [{"event": "near", "found": ["b1"]}],
           [{"event": "far", "positions": {"hand": [0, 200, 150]}},
            {"detector": "change-detector", "value": "decreased", "at": [0, 200, 25]}]]
PLACE_ON_TABLE_ALIGNED = [
    DOWN, [{"event": "near", "found": ["table"]}], [{"event": "join"}],
    [{"event": "split"}, {"detector": "coplanar-detector", "value": "positive"}],
    [{"event": "far"}, {"detector": "change-detector", "value": "increased", "at": [100, 262, 25]}],
]


@pytest.mark.parametrize("named,other", [(("b3",), "b3"), ((), "table")],
                         ids=["TableV-ALIGN-neighbour-named", "TableV-ALIGN-none-named-target"])
def test_align_relation_names_the_neighbour(monkeypatch, named, other):
    original = replay.ReplayDetector.compare

    def compare(self, first, last, act, env):
        found = original(self, first, last, act, env)
        if found is not None and self.name == "coplanar-detector":
            return Detection(value=found.value, position=found.position, found=named)
        return found

    monkeypatch.setattr(replay.ReplayDetector, "compare", compare)
    rec = run_script(RULES, [LOCATE, ENTER, *PICK_B1, *PLACE_ON_TABLE_ALIGNED])
    place = rec.root.history[-1]
    assert [n.operation for n in place.history] == [
        "APPROACH-WITH-OBJ", "ALIGN", "DEPART-WITH-OBJ"]
    assert [r.to_json() for r in rec.env.relations if r.type == "coplanar"] == [
        ["coplanar", "b1", other]]
