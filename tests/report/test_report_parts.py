"""The report's parts without a browser: tables, the motion plot, state pictures, strips."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from types import SimpleNamespace as NS

import numpy as np
import pytest

from lbw_engine.rules import load_rules
from lbw_engine.see.motionfeatures import down_angle
from perception.pictures.motionplot import (
    Scales,
    cuts,
    feature_runs,
    motion_plot_svg,
    speed_thresholds,
)
from perception.pictures.motiontrace import (
    LoggedEvent,
    MotionRecorder,
    MotionSample,
    MotionTrace,
    Segment,
    segments,
)
from perception.pictures.report import frame_label, strip_html, zoomable
from perception.pictures.statepics import (
    EXPECTED_COLOR,
    MEASURED_COLOR,
    Box,
    corners,
    draw_boxes,
    final_boxes,
    initial_boxes,
)
from perception.pictures.tables import cell, execution_tables
from perception.vision.camera import default_cameras

RULES = load_rules()
FEATURES = RULES.motion_features
SVG = "{http://www.w3.org/2000/svg}"


class _Tables(HTMLParser):
    """Tables by id: rows of cell texts (header row included); other ids seen."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self.ids: list[str] = []
        self._table: list[list[str]] | None = None
        self._cell: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        ident = dict(attrs).get("id")
        if ident:
            self.ids.append(ident)
        if tag == "table":
            self._table = self.tables.setdefault(ident, [])
        elif tag == "tr" and self._table is not None:
            self._table.append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None and self._table is not None:
            self._table[-1].append("".join(self._cell))
            self._cell = None
        elif tag == "table":
            self._table = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


# -- execution.json as tables (design.md's keys; each may be absent) --------------------------

REPORTS = {
    "verified, verification a bool": (
        {"success": True, "verification": True, "mismatches": []},
        {"verdict": [["success (the cameras' verdict)", "✓ yes"], ["verification", "✓ yes"]]},
        ["mismatches", "monitor-none"]),
    "verification from two sources": (
        {"success": False, "verification": {"cameras": False, "ground_truth": True},
         "failure": "verification: tow1-b3 is 40 mm off"},
        {"verdict": [["success (the cameras' verdict)", "✗ no"],
                     ["verification: cameras", "✗ no"], ["verification: ground_truth", "✓ yes"],
                     ["failure", "verification: tow1-b3 is 40 mm off"]]},
        ["monitor-none"]),
    "mismatches and positions": (
        {"success": False, "mismatches": [{"kind": "position", "object": "b1", "expected": [0, 0,
                                           10], "measured": [40, 0, 10], "message": "b1 moved"}],
         "expected": {"positions": {"b1": [0.0, 0.0, 10.0]}, "relations": [["on", "b1", "table"]]},
         "positions": {"b1": [40.0, 0.0, 10.0]}, "relations": [["on", "b1", "table"]]},
        {"mismatches": [["message", "kind", "object", "expected", "measured"],
                        ["b1 moved", "position", "b1", "(0, 0, 10)", "(40, 0, 10)"]],
         "positions": [["object", "expected", "measured", "distance mm"],
                       ["b1", "(0, 0, 10)", "(40, 0, 10)", "40"]],
         "relations": [["relation", "expected", "measured"], ["on b1 table", "✓ yes", "✓ yes"]]},
        ["monitor-none"]),
    "monitor, nothing happened": (
        {"success": True, "monitor": {"detections": [], "repairs": []}},
        {}, ["monitor-detections", "monitor-repairs"]),
    "monitor with a detection and a repair": (
        {"success": True, "monitor": {
            "detections": [{"operator": "achieve02", "object": "b2", "expected": "held",
                            "observed": "on table", "t": 12.5}],
            "repairs": [{"operator": "achieve02", "commands": 9}]}},
        {"monitor-detections": [["operator", "object", "expected", "observed", "t"],
                                ["achieve02", "b2", "held", "on table", "12.5"]],
         "monitor-repairs": [["operator", "commands"], ["achieve02", "9"]]},
        []),
    "a key nobody expected": (
        {"success": True, "surprise": {"a": 1}},
        {"other": [["key", "value"], ["surprise", "a: 1"]]}, ["monitor-none"]),
}


@pytest.mark.parametrize("case", REPORTS)
def test_execution_json_as_tables(case):
    report, tables, ids = REPORTS[case]
    parsed = _Tables(execution_tables(report))
    for ident, rows in tables.items():
        got = parsed.tables[ident]
        assert got[1:] == rows if ident == "verdict" else got == rows, ident
    for ident in ids:
        assert ident in parsed.ids
    assert "{'" not in execution_tables(report)  # nothing printed as a Python dict


@pytest.mark.parametrize("value,html", [
    (True, '<span class="ok">✓ yes</span>'), (False, '<span class="bad">✗ no</span>'),
    (None, "-"), (2.50, "2.5"), ([1.0, 2.5, 3], "(1, 2.5, 3)"), ("a<b", "a&lt;b"),
    ({"k": [1, 2]}, "k: (1, 2)"), (["x", True], 'x, <span class="ok">✓ yes</span>'),
])
def test_cell(value, html):
    assert cell(value) == html


# -- the motion plot -----------------------------------------------------------------------------

@pytest.mark.parametrize("velocity,angle", [
    ((0, 0, -1), 0.0), ((0, 0, 1), 180.0), ((1, 0, 0), 90.0), ((0, 1, -1), 45.0),
    ((0, 0, 0), None),
])
def test_down_angle(velocity, angle):
    got = down_angle(velocity)
    assert got == angle if angle is None else got == pytest.approx(angle)


def _seg(level, name, t0, t1, first, last, op=None):
    return Segment(level, name, name.rstrip("0123456789"), op, t0, t1, first, last)


TRACE = MotionTrace(
    samples=[MotionSample(t, v, a, 50.0) for t, v, a in
             [(0.0, 5.0, 10.0), (0.1, 10.0, 80.0), (0.2, 50.0, 130.0), (0.3, 200.0, 90.0),
              (1.0, 20.0, None)]],  # a gap after 0.3 s: the curves break there
    events=[LoggedEvent(0.0, "M", "small-motion", "a"), LoggedEvent(0.1, "M", "small-motion", "a"),
            LoggedEvent(0.2, "M", "small-motion", "b"), LoggedEvent(0.9, "M", "small-motion", "b"),
            LoggedEvent(0.5, "M", "near", None)],
    segments=[_seg(1, "T1", 0.0, 0.5, "e0", "e1", "OP1"), _seg(2, "S1", 0.0, 0.25, "e2", "e3"),
              _seg(2, "S2", 0.25, 0.5, "e3", "e1"), _seg(1, "T2", 0.5, 1.0, "e1", None, "OP2")],
    t_end=1.0)


def test_cuts_name_the_events_that_made_them():
    got = [(t, level, names) for t, level, names, _ in cuts(TRACE.segments)]
    assert got == [(0.0, 1, ["e0", "e2"]), (0.25, 2, ["e3"]), (0.5, 1, ["e1"]), (1.0, 1, [])]
    why = cuts(TRACE.segments)[2][3]
    assert why == "t = 0.50 s: T1 (OP1) ends on :e1; S2 (?) ends on :e1; T2 (OP2) begins on :e1"


def test_feature_runs_join_equal_values_and_break_at_gaps():
    assert feature_runs(TRACE.events, "small-motion", 0.1) == [
        (0.0, 0.2, "a", "M"), (0.2, 0.30000000000000004, "b", "M"), (0.9, 1.0, "b", "M")]


def test_speed_thresholds_come_from_the_rules():
    got = speed_thresholds(FEATURES)
    want = {}
    for k, (low, high) in enumerate(FEATURES.ranges.values(), 1):
        want.setdefault(float(low), []).append(f"V_L{k}")
        want.setdefault(float(high), []).append(f"V_H{k}")
    assert [(v, name) for v, name, _ in got] == [(v, " = ".join(n)) for v, n in
                                                 sorted(want.items())]


def test_plot_puts_samples_and_thresholds_on_one_scale():
    svg = ET.fromstring(motion_plot_svg(TRACE, FEATURES))
    sc = Scales(TRACE, FEATURES)
    lines = {float(g.get("data-value")): float(g.find(f"{SVG}line").get("y1"))
             for g in svg.iter(f"{SVG}g") if g.get("class") == "threshold speed"}
    for v, y in lines.items():
        assert y == pytest.approx(sc.speed(v), abs=0.06)
    speed = [p for p in svg.iter(f"{SVG}polyline") if p.get("class") == "speed"]
    assert len(speed) == 2  # broken at the gap
    points = [tuple(map(float, xy.split(","))) for xy in speed[0].get("points").split()]
    for (x, y), sample in zip(points, TRACE.samples, strict=False):
        assert x == pytest.approx(sc.x(sample.t), abs=0.06)
        if sample.speed in lines:  # a sample at a threshold's speed lies on its line
            assert y == pytest.approx(lines[sample.speed], abs=0.06)
    angles = {float(g.get("data-value")) for g in svg.iter(f"{SVG}g")
              if g.get("class") == "threshold angle"}
    assert angles == {FEATURES.angle_down, FEATURES.angle_up}
    cut_x = [float(g.find(f"{SVG}line").get("x1")) for g in svg.iter(f"{SVG}g")
             if g.get("class") == "cut"]
    assert cut_x == pytest.approx([sc.x(t) for t in (0.0, 0.25, 0.5, 1.0)], abs=0.06)
    assert all(m.find(f"{SVG}title") is not None for m in svg.iter()
               if m.get("class") in ("cut", "feature", "event"))


def test_segments_walk_the_act_tree_depth_first():
    def node(name, level, t0, t1, *kids):
        return NS(name=name, motion=name[:-1], level=level, operation=None, t_start=t0,
                  t_end=t1, initial_event=None, final_event=None, history=list(kids))
    root = node("R1", 0, 0, None, node("A1", 1, 0, 2, node("B1", 2, 0, 1), node("B2", 2, 1, 2)),
                node("A2", 1, 2, 3), node("A3", 1, 3, None))  # A3 never ended
    assert [s.name for s in segments(root)] == ["A1", "B1", "B2", "A2"]


@pytest.mark.parametrize("tracking,steady,kept", [(True, True, 1), (True, False, 0),
                                                  (False, True, 0)])
def test_motion_recorder_keeps_what_the_tracker_would_answer(tracking, steady, kept):
    hand = NS(tracking=tracking, steady=steady, velocity=(0.0, 30.0, -40.0),
              hand=np.array([0.0, 0.0, 80.0]))
    recorder = MotionRecorder()
    recorder(NS(t=1.5), None, hand)
    assert len(recorder.trace.samples) == kept and recorder.trace.t_end == 1.5
    if kept:
        sample = recorder.trace.samples[0]
        assert (sample.speed, sample.z) == (50.0, 80.0)
        assert sample.angle == pytest.approx(math.degrees(math.acos(0.8)))


# -- state pictures ---------------------------------------------------------------------------

def test_boxes_are_drawn_where_the_cameras_see_them():
    cams = default_cameras()
    views = {"top": np.zeros((256, 256), np.uint8), "side": np.zeros((256, 256), np.uint8)}
    box = Box("b", (0.0, 200.0, 25.0), (60.0, 60.0, 50.0), EXPECTED_COLOR)
    img = draw_boxes(views, [box], cams, scale=2)
    assert img.shape == (512, 1028, 3)
    for k, name in enumerate(("top", "side")):
        for u, v in cams[name].project(corners(box.center, box.size)) * 2:
            x, y = int(round(u)) + k * 516, int(round(v))
            patch = img[y - 1:y + 2, x - 1:x + 2].reshape(-1, 3).astype(int)
            # anti-aliased edges: near the colour (black, the background, is 455 away)
            assert np.abs(patch - EXPECTED_COLOR).sum(axis=1).min() < 150, (name, u, v)
    assert img[:40, 100:200].max() == 0  # and nothing far from it


def test_initial_and_final_boxes_from_execution_json():
    report = {"initial_state": {"measured": [
        {"shape": "brick", "position": [1.0, 2.0, 25.0], "size": [30, 30, 50]},
        {"shape": "cube", "position": [9.0, 9.0, 20.0], "size": [40, 40, 40]}],
        "matching": {"b1": [1.0, 2.0, 25.0]}},
        "expected": {"positions": {"b1": [5.0, 5.0, 25.0]}},
        "positions": {"b1": [6.0, 5.0, 25.0]}}
    assert [(b.label, b.color) for b in initial_boxes(report)] == [
        ("b1", MEASURED_COLOR), ("cube (not in the plan)", MEASURED_COLOR)]
    final = final_boxes(report, {"b1": (30, 30, 50)})
    assert [(b.center, b.color) for b in final] == [((6.0, 5.0, 25.0), MEASURED_COLOR),
                                                    ((5.0, 5.0, 25.0), EXPECTED_COLOR)]


# -- frame strips and zoom --------------------------------------------------------------------

def test_strip_labels_each_frame_with_its_own_time():
    frames = [(t, np.zeros((8, 8, 3), np.uint8)) for t in (0.0, 1.005, 30.52, 155.5)]
    html = strip_html("s", frames)
    assert re.findall(r'data-label="([^"]*)"', html) == [frame_label(t) for t, _ in frames]
    assert frame_label(30.52) == "t = 30.52 s"
    assert 'max="3"' in html


def test_zoomable_caps_the_fit_at_a_multiple_of_the_natural_width():
    html = zoomable("v", '<svg xmlns="http://www.w3.org/2000/svg" width="400" height="10">'
                         "</svg>")
    assert 'style="max-width:calc(var(--zoom) * 600px)"' in html and 'data-for="v"' in html
