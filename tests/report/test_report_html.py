"""report.html is one self-contained file that renders in headless Chromium without errors."""

import json
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from lbw_engine.rules import load_rules
from lbw_engine.understand import write_plan_text
from perception.pictures.report import pick_frames, render_report, timeline_svg
from perception.vision.camera import default_cameras
from perception.world.demonstrator import Demonstration
from perception.world.groundtruth import ground_truth
from perception.world.render import Renderer
from perception.world.scenario import load

RULES = load_rules()

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists()
                                        else None)
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--enable-logging=stderr", "--v=0", "--dump-dom"]


def _need_chromium():
    """Skip without Chromium, except in CI (CI=true), where its absence is a failure."""
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":
            pytest.fail("chromium is not installed in CI (.ci/run installs it)")
        pytest.skip("chromium is not installed (apt-get install -y chromium)")


def _open(path: Path, tmp_path: Path) -> tuple[str, list[str]]:
    """Load ``path`` in headless Chromium: (the DOM after scripts ran, console messages)."""
    profile = tmp_path / f"profile-{path.stem}"
    proc = subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={profile}", path.as_uri()],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    console = [line for line in proc.stderr.splitlines() if ":CONSOLE" in line]
    return proc.stdout, console


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """A report of the bundled build-table: Fig. 20's actions, its plan, real frames."""
    sc = load(ROOT / "scenarios" / "build-table.yaml")
    demo = Demonstration(sc)
    truth = [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
             for t in ground_truth(sc, RULES, demo)]
    renderer = Renderer(default_cameras(), pixel_noise=sc.noise.pixel, seed=sc.seed)
    frames = []
    for i, (t, scene) in enumerate(demo):
        if i % 30 == 0:
            v = renderer.render(scene)
            frames.append((t, np.hstack([v["top"], v["side"]])))
        if i > 1500:
            break
    actions = json.loads((DATA / "fig20-build-table.actions.json").read_text())
    plan = json.loads((DATA / "build-table.plan.json").read_text())
    html = render_report(title="build-table", scenario_text=Path(sc.file).read_text(),
                         actions=actions, truth=truth, plan=plan,
                         plan_text=write_plan_text(plan), commands_text="(amove ...)",
                         execution={"success": True, "stage": "verification", "commands": 45},
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


def test_report_renders_without_console_errors(report, tmp_path):
    _need_chromium()
    path, actions, plan = report
    dom, console = _open(path, tmp_path)
    assert console == []
    assert 'data-ready="yes"' in dom  # the page's script ran to its end
    for ident in ("scenario", "video", "frames", "timeline", "plan", "plan-text", "commands",
                  "verification"):
        assert f'id="{ident}"' in dom, ident
    # the timeline has one bar per recognized operation (plus the ground truth row) ...
    assert len(re.findall(r'class="op recognized"', dom)) == len(actions["operations"])
    # ... and the plan picture one box per operator
    for name in plan["operators"]:
        assert f'id="op-{name}"' in dom, name


def test_console_check_catches_errors(tmp_path):
    """The console check can fail: a page with a script error is caught."""
    _need_chromium()
    bad = tmp_path / "bad.html"
    bad.write_text("<html><body><script>notDefined();</script></body></html>")
    _, console = _open(bad, tmp_path)
    assert any("notDefined" in line for line in console)


def test_timeline_rows():
    truth = [{"operation": "A", "t_start": 0.0, "t_end": 2.0},
             {"operation": "B", "t_start": 2.0, "t_end": 5.0}]
    ops = [{"operation": "A", "t_start": 0.1, "t_end": 2.2},
           {"operation": None, "t_start": 2.2, "t_end": None}]
    svg = ET.fromstring(timeline_svg(truth, ops))
    groups = svg.findall("{http://www.w3.org/2000/svg}g")
    assert [g.get("class") for g in groups] == ["op truth"] * 2 + ["op recognized"] * 2
    bar = groups[1].find("{http://www.w3.org/2000/svg}rect")
    assert float(bar.get("width")) == pytest.approx(3.0 * 8.0)  # 3 s at 8 px/s


def test_run_report_of_a_real_run(tmp_path):
    """watch (with the monitor) → analyze → execute (recorded) → report.html, in Chromium."""
    from lbw_engine.do import plan as planmod
    from lbw_engine.pipeline.execute import execute_plan
    from lbw_engine.rules import load_rules
    from lbw_engine.see.actions import to_actions
    from lbw_engine.understand import RelationTable, analyze, parse_actions
    from perception.pictures.overlay import ExecutionRecorder, record_demonstration
    from perception.pictures.report import run_report
    from perception.world.generator import generate

    sc = generate(5, structures=["tower"]).scenario()
    rec, _, kept = record_demonstration(sc, load_rules(), None, keep_every=3.0,
                                        scale=1)
    actions = to_actions(rec)
    arules = load_rules().analysis
    plan = analyze(parse_actions(actions, RelationTable(arules.tolerance)), arules).plan
    recorder = ExecutionRecorder(None, every=10, keep_every=5.0, scale=1)
    result = execute_plan(planmod.parse(plan, file="plan.json"), sc, load_rules(),
                          on_step=recorder)
    html = run_report(sc, load_rules(), actions, plan, write_plan_text(plan), result,
                      frames=kept + recorder.kept)
    path = tmp_path / "report.html"
    path.write_text(html)
    assert html.count('class="frame"') == min(60, len(kept) + len(recorder.kept))
    _need_chromium()
    dom, console = _open(path, tmp_path)
    assert console == [] and 'data-ready="yes"' in dom
    assert len(re.findall(r'class="op recognized"', dom)) == len(actions["operations"])
    assert ('class="ok"' in dom.split('id="verification"')[1]) == result.success
    for name in plan["operators"]:
        assert f'id="op-{name}"' in dom, name
