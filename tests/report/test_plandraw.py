"""Plan pictures (Fig. 13 / Fig. 22 style): one box per operator, arrows and arcs per plot."""

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import cv2
import numpy as np
import pytest

from lbw_engine.understand import analyze_file
from perception.pictures.plandraw import plan_picture, png_bytes, svg_text, to_image

DATA = Path(__file__).resolve().parents[1] / "data"
SVG = "{http://www.w3.org/2000/svg}"


def _plans():
    """The bundled test plans, plus the plan `lbw analyze` learns from Fig. 12's actions."""
    out = {p.name: json.loads(p.read_text()) for p in sorted(DATA.glob("*.plan.json"))}
    out["fig12-analyzed"] = analyze_file(DATA / "fig12-inverted-arch.actions.json").plan
    return out


PLANS = _plans()


def _plot_counts(plot):
    """(sequence arrows, parallel arcs) a plot should produce."""
    if plot[0] == "$action":
        return 0, 0
    subs = [_plot_counts(p) for p in plot[1:]]
    arrows = sum(a for a, _ in subs) + (len(plot) - 2 if plot[0] == "$sequence" else 0)
    arcs = sum(b for _, b in subs) + (1 if plot[0] == "$parallel" and len(plot) > 2 else 0)
    return arrows, arcs


def _leaves(plan):
    """Plot names that are not operators: the recognized operations."""
    ops = plan["operators"]

    def names(plot):
        return [plot[1]] if plot[0] == "$action" else [n for p in plot[1:] for n in names(p)]

    return {n for op in ops.values() for n in names(op["plot"]) if n not in ops}


@pytest.mark.parametrize("name", sorted(PLANS))
def test_svg_is_xml_with_one_box_per_operator(name):
    plan = PLANS[name]
    root = ET.fromstring(svg_text(plan))
    groups = root.findall(f"{SVG}g")
    ops = [g.get("id")[3:] for g in groups if g.get("class") == "operator"]
    leaves = [g.get("id")[5:] for g in groups if g.get("class") == "leaf"]
    assert sorted(ops) == sorted(plan["operators"])  # each operator exactly once
    assert set(leaves) == _leaves(plan) and len(leaves) == len(set(leaves))
    for g in groups:
        if g.get("class") == "operator":
            op = plan["operators"][g.get("id")[3:]]
            texts = [t.text for t in g.findall(f"{SVG}text")]
            assert texts[0] == f"{op['class']} {g.get('id')[3:]}"
            assert texts[1] == "base: " + (" ".join(op["base"]) or "-")
            assert texts[2] == "target: " + (" ".join(op["target"]) or "-")


@pytest.mark.parametrize("name", sorted(PLANS))
def test_sequence_arrows_and_parallel_arcs(name):
    plan = PLANS[name]
    arrows = sum(_plot_counts(op["plot"])[0] for op in plan["operators"].values())
    arcs = sum(_plot_counts(op["plot"])[1] for op in plan["operators"].values())
    root = ET.fromstring(svg_text(plan))
    lines = root.findall(f"{SVG}polyline")
    assert sum(p.get("class") == "sequence" for p in lines) == arrows
    assert sum(p.get("class") == "parallel" for p in lines) == arcs
    assert all(p.get("marker-end") for p in lines if p.get("class") == "sequence")


def test_inverted_arch_has_a_parallel_build():
    """Fig. 13: the two bricks on the plank are achieved in parallel (one arc)."""
    root = ET.fromstring(svg_text(PLANS["fig12-analyzed"]))
    assert sum(p.get("class") == "parallel" for p in root.findall(f"{SVG}polyline")) == 1


@pytest.mark.parametrize("name", sorted(PLANS))
def test_png_draws_every_box(name):
    plan = PLANS[name]
    pic = plan_picture(plan)
    img = cv2.imdecode(np.frombuffer(png_bytes(plan), np.uint8), cv2.IMREAD_COLOR)
    assert img.shape == (pic.height, pic.width, 3)
    assert np.array_equal(img, to_image(pic))
    for r in pic.rects:  # the box outline and its text are drawn inside the box's area
        patch = img[int(r.y):int(r.y + r.h) + 1, int(r.x):int(r.x + r.w) + 1]
        assert (patch.min(axis=2) < 100).sum() > 20, r.ident
    for a in pic.rects:  # boxes never overlap
        for b in pic.rects:
            if a is not b:
                assert (a.x + a.w <= b.x or b.x + b.w <= a.x or a.y + a.h <= b.y
                        or b.y + b.h <= a.y), (a.ident, b.ident)
