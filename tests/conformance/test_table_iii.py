"""Table III, one case per row: each visual event, the ENV-node classes that
answer it and the detector they ask; and the numeric constants of the
footnotes (4, 6, 10, 12)."""

import pytest

from lbw_engine.rules import load_rules

RULES = load_rules()

ROWS = [  # (case id, event, detector, ENV-node classes)
    ("TableIII-row1-loc-exist", "loc-exist", "object-finder", ("World",)),
    ("TableIII-row2-found-moving", "found-moving", "motion-detector", ("World",)),
    ("TableIII-row3-disappeared", "disappeared", "hand-tracker", ("HandLoc", "World")),
    ("TableIII-row4-large-motion", "large-motion", "hand-tracker", ("HandLoc",)),
    ("TableIII-row5-small-motion", "small-motion", "hand-tracker", ("HandLoc",)),
    ("TableIII-row6-near", "near", "visual-search", ("HandLoc", "Loc")),
    ("TableIII-row7-far", "far", "hand-tracker", ("HandLoc", "Loc")),
    ("TableIII-row8-join", "join", "hand-object-tracker", ("HandLoc", "Loc")),
    ("TableIII-row9-split", "split", "hand-object-tracker", ("HandLoc", "Loc")),
]


@pytest.mark.parametrize("event,detector,nodes", [r[1:] for r in ROWS], ids=[r[0] for r in ROWS])
def test_table_iii_row(event, detector, nodes):
    spec = RULES.events[event]
    assert (spec.detector, spec.nodes) == (detector, nodes)
    assert not RULES.detectors[detector].builtin  # answered by perception or replay


def test_only_the_paper_events_and_true():
    assert set(RULES.events) == {r[1] for r in ROWS} | {"true"}
    assert RULES.detectors[RULES.events["true"].detector].builtin == "constant"


def test_footnote_constants():
    c = RULES.constants
    assert c["attention-region"] == (50, 50, 45)
    assert c["search-cycle-limit"] == 4
    assert c["repositioning-distance"] == 120
    assert c["motion-detector-interval"] == 0.0835
