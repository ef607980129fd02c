"""Table IV, one case per row: the hand's 3-D velocity gives a qualitative motion
value, with the thresholds of footnote 11 (angles from straight down)."""

import math

import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.motionfeatures import classify

RULES = load_rules()
TABLE = RULES.motion_features


def polar(speed, angle_from_down):
    """A velocity of ``speed`` mm/s at ``angle_from_down`` degrees from straight down."""
    a = math.radians(angle_from_down)
    return (speed * math.sin(a), 0.0, -speed * math.cos(a))


ROWS = [  # (case id, velocity, query event, expected value)
    ("TableIV-row1-staying", polar(5, 0), "small-motion", "staying"),
    ("TableIV-row2-moving-up", polar(30, 170), "small-motion", "moving-up"),
    ("TableIV-row3-moving-down", polar(30, 20), "small-motion", "moving-down"),
    ("TableIV-row4-moving-laterally", polar(30, 90), "small-motion", "moving-laterally"),
    ("TableIV-row5-moving-fast", polar(80, 90), "small-motion", "moving-fast"),
]


@pytest.mark.parametrize("velocity,event,expected", [r[1:] for r in ROWS], ids=[r[0] for r in ROWS])
def test_table_iv_row(velocity, event, expected):
    assert classify(velocity, event, TABLE) == expected


def test_every_rule_row_is_covered():
    assert set(TABLE.values()) == {r[3] for r in ROWS}


def test_footnote_11_thresholds():
    assert TABLE.ranges["small-motion"] == (10, 50)
    assert TABLE.ranges["large-motion"] == (50, 10000)
    assert (TABLE.angle_down, TABLE.angle_up) == (75, 120)


BOUNDARIES = [  # the second speed range, and the angle thresholds from either side
    ("large-range-slow-is-staying", polar(40, 90), "large-motion", "staying"),
    ("large-range-moving-up", polar(400, 180), "large-motion", "moving-up"),
    ("angle-74-is-down", polar(30, 74), "small-motion", "moving-down"),
    ("angle-76-is-lateral", polar(30, 76), "small-motion", "moving-laterally"),
    ("angle-119-is-lateral", polar(30, 119), "small-motion", "moving-laterally"),
    ("angle-121-is-up", polar(30, 121), "small-motion", "moving-up"),
    ("speed-9.9-is-staying", polar(9.9, 0), "small-motion", "staying"),
    ("speed-50.1-is-fast", polar(50.1, 0), "small-motion", "moving-fast"),
]


@pytest.mark.parametrize("velocity,event,expected", [r[1:] for r in BOUNDARIES],
                         ids=[r[0] for r in BOUNDARIES])
def test_thresholds(velocity, event, expected):
    assert classify(velocity, event, TABLE) == expected
