"""Table V, one case per row: the feature values measured at a motion's end
classify it into one operation. Features are computed by the engine from the
environment model (Hold, the kind of target) and from detector snapshots
(SilDiff, CoplDet), as at a real segmentation point."""

import pytest

from lbw_engine.model.env import EnvModel, Relation
from lbw_engine.rules import load_rules
from lbw_engine.see.actmodel import ActNode, classify, compute_features
from lbw_engine.see.detectors import Detection

RULES = load_rules()


def answer(detector: str, value: str):
    """What ``detector`` answers for the Table V value ``value`` (operations.yaml)."""
    return next(f.answers[value] for f in RULES.features.values() if f.detector == detector)


def env_with(holding: bool) -> EnvModel:
    env = EnvModel(RULES)
    env.locate([("b1", "brick", (30, 30, 50), (0, 200, 25))])
    if holding:
        env.relations.append(Relation(RULES.hold_relation, "hand", "b1"))
    return env


ROWS = [  # (case id, motion, final event, holding, target, snapshot diffs, operation)
    ("TableV-row1-Task-BUILD", "Task", "disappeared", False, (), {}, "BUILD"),
    ("TableV-row2-Transfer-REACH", "Transfer", "near", False, ("b1",), {}, "REACH"),
    ("TableV-row3-Transfer-REACH-WITH-OBJ", "Transfer", "near", True, ("table",), {},
     "REACH-WITH-OBJ"),
    ("TableV-row4-Transfer-WITHDRAW", "Transfer", "found-moving", False, (), {}, "WITHDRAW"),
    ("TableV-row5-LocalMotion-PICK", "LocalMotion", "far", False, ("b1",),
     {"change-detector": "decreased"}, "PICK"),
    ("TableV-row6-LocalMotion-PLACE-ON-TABLE", "LocalMotion", "far", True, ("table",),
     {"change-detector": "increased"}, "PLACE-ON-TABLE"),
    ("TableV-row7-LocalMotion-PLACE-ON-BLOCK", "LocalMotion", "far", True, ("b1",),
     {"change-detector": "increased"}, "PLACE-ON-BLOCK"),
    ("TableV-row8-LocalMotion-NO-OP", "LocalMotion", "far", False, ("b1",),
     {"change-detector": "no-change"}, "NO-OP"),
    ("TableV-row9-Approach-APPROACH", "Approach", "join", False, ("b1",), {}, "APPROACH"),
    ("TableV-row10-Approach-APPROACH-WITH-OBJ", "Approach", "join", True, ("b1",), {},
     "APPROACH-WITH-OBJ"),
    ("TableV-row11-Depart-DEPART", "Depart", "far", False, ("b1",), {}, "DEPART"),
    ("TableV-row12-Depart-DEPART-WITH-OBJ", "Depart", "far", True, ("b1",), {},
     "DEPART-WITH-OBJ"),
    ("TableV-row13-FineMotion-ALIGN", "FineMotion", "split", True, ("b1",),
     {"coplanar-detector": "positive"}, "ALIGN"),
    ("TableV-row14-FineMotion-NO-OP", "FineMotion", "split", True, ("b1",),
     {"coplanar-detector": "unchanged"}, "NO-OP"),
]


@pytest.mark.parametrize("motion,event,holding,target,diffs,operation", [r[1:] for r in ROWS],
                         ids=[r[0] for r in ROWS])
def test_table_v_row(motion, event, holding, target, diffs, operation):
    env = env_with(holding)
    node = ActNode(motion, f"{motion}1", RULES.motions[motion].level, None, ("hand",), target)
    # the detectors answer in their own words; the rules' feature tables translate them
    compared = {name: Detection(value=answer(name, value)) for name, value in diffs.items()}
    features = compute_features(RULES, node, event, env, compared)
    assert classify(RULES, motion, features) == operation


def test_every_rule_row_is_covered():
    rows = {(r.motion, r.operation) for rs in RULES.classification.values() for r in rs}
    assert rows == {(r[1], r[6]) for r in ROWS}


def test_snapshot_features_name_their_detectors():
    """SilDiff is taken for LocalMotion and CoplDet for FineMotion, at start and end."""
    assert RULES.snapshot_detectors("LocalMotion") == ("change-detector",)
    assert RULES.snapshot_detectors("FineMotion") == ("coplanar-detector",)
    assert RULES.snapshot_detectors("Transfer") == ()
