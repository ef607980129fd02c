"""report.html from recorded data files (no run): the bundled build-table, Fig. 20's actions.

Its plan is the widest of the bundled ones (the one issue #14 found cut off);
the page is checked in headless Chromium at two widths.
"""

import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from lbw_engine.rules import load_rules
from lbw_engine.understand import write_plan_text
from perception.pictures.report import pick_frames, render_report
from perception.pictures.timeline import PX_PER_S, timeline_svg
from perception.vision.camera import default_cameras
from perception.world.demonstrator import Demonstration
from perception.world.groundtruth import ground_truth
from perception.world.render import Renderer
from perception.world.scenario import load

from .browser import Chromium
from .conftest import need_chromium

RULES = load_rules()
ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """A report of the bundled build-table: Fig. 20's actions, its plan, rendered frames."""
    sc = load(ROOT / "scenarios" / "build-table.yaml")
    demo = Demonstration(sc)
    truth = [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
             for t in ground_truth(sc, RULES, demo)]
    renderer = Renderer(default_cameras(), pixel_noise=sc.noise.pixel, seed=sc.seed)
    frames = []
    for i, (t, scene) in enumerate(demo):
        if i % 60 == 0:
            v = renderer.render(scene)
            frames.append((t, np.hstack([v["top"], v["side"]])))
        if i > 1500:
            break
    actions = json.loads((DATA / "fig20-build-table.actions.json").read_text())
    plan = json.loads((DATA / "build-table.plan.json").read_text())
    html = render_report(title="build-table", scenario_text=Path(sc.file).read_text(),
                         actions=actions, truth=truth, plan=plan,
                         plan_text=write_plan_text(plan), commands_text="(amove ...)",
                         execution={"success": True, "stage": "verification", "commands": 45,
                                    "verification": {"cameras": True, "ground_truth": True}},
                         frames=pick_frames(frames, 20))
    path = tmp_path_factory.mktemp("report") / "report.html"
    path.write_text(html)
    return path, actions, plan


def test_report_is_self_contained(report):
    path, *_ = report
    text = path.read_text()
    # nothing fetched from elsewhere: every src/href is inline or a fragment
    for ref in re.findall(r'(?:src|href)="([^"]*)"', text):
        assert ref.startswith(("data:", "#")), ref
    assert "<link" not in text and "@import" not in text


@pytest.mark.parametrize("width", [1280, 800])
def test_wide_plan_fits_the_page(report, tmp_path, width):
    need_chromium()
    path, actions, plan = report
    with Chromium(tmp_path / "profile") as browser:
        page = browser.open(path, width=width)
        assert page.problems() == [] and page.js("document.body.dataset.ready") == "yes"
        ids = page.js("[...document.querySelectorAll('#plan-view g.operator')].map(g => g.id)")
        assert sorted(ids) == sorted(f"op-{name}" for name in plan["operators"])
        box = page.js("""(() => { const b = document.querySelector('#plan-view svg')
            .getBoundingClientRect(); return [b.left, b.right, b.width,
            document.documentElement.clientWidth]; })()""")
        assert box[0] >= 0 and box[1] <= box[3] and box[2] > 0.5 * (width - 60), box
        bars = page.js("document.querySelectorAll('#timeline .op.recognized').length")
        assert bars == len(actions["operations"])


def test_console_check_catches_errors(tmp_path):
    """The console check can fail: a page with a script error is caught."""
    need_chromium()
    bad = tmp_path / "bad.html"
    bad.write_text("<html><body><script>notDefined();</script></body></html>")
    with Chromium(tmp_path / "profile") as browser:
        page = browser.open(bad)
        assert any("notDefined" in p for p in page.problems())


def test_timeline_rows():
    truth = [{"operation": "A", "t_start": 0.0, "t_end": 2.0},
             {"operation": "B", "t_start": 2.0, "t_end": 5.0}]
    ops = [{"operation": "A", "t_start": 0.1, "t_end": 2.2},
           {"operation": None, "t_start": 2.2, "t_end": None}]
    svg = ET.fromstring(timeline_svg(truth, ops))
    groups = svg.findall(f"{SVG}g")
    assert [g.get("class") for g in groups] == ["op truth"] * 2 + ["op recognized"] * 2
    bar = groups[1].find(f"{SVG}rect")
    assert float(bar.get("width")) == pytest.approx(3.0 * PX_PER_S)  # 3 s
    assert [g.find(f"{SVG}title").text for g in groups] == [
        "ground truth #1: A, 0.00-2.00 s", "ground truth #2: B, 2.00-5.00 s",
        "recognized #1: A, 0.10-2.20 s", "recognized #2: ?, 2.20-5.00 s"]  # open: to the end
