"""lbw run's pictures: monitor and execution videos, plan pictures and report.html, staged."""

import xml.etree.ElementTree as ET

import pytest

from lbw_engine.cli.pictures import video_files
from lbw_engine.outputs import OutputDir

from .conftest import RecordedRun


def test_run_with_pictures_stages_every_file(recorded_run: RecordedRun):
    names = {p.name for p in recorded_run.out.iterdir()}
    assert {"demonstration.mp4", "execution.mp4", "report.html", "plan.svg", "plan.png",
            "actions.json", "plan.json", "plan.txt", "execution.json"} <= names
    verdict = recorded_run.json("execution.json")
    assert verdict["recognition"]["exact"] and verdict["success"], verdict.get("failure")
    plan = recorded_run.json("plan.json")
    svg = ET.parse(recorded_run.out / "plan.svg").getroot()
    boxes = [g for g in svg.iter("{http://www.w3.org/2000/svg}g") if g.get("class") == "operator"]
    assert len(boxes) == len(plan["operators"])
    html = (recorded_run.out / "report.html").read_text()
    assert 'id="timeline"' in html and f'id="op-{plan["root"]}"' in html
    assert "verified: the executed structure matches the plan" in html


@pytest.mark.parametrize("video,report,where", [
    (True, True, "staged"),
    (True, False, "staged"),
    (False, True, "scratch"),  # made for the report to embed, never published
    (False, False, None),  # not recorded at all
])
def test_where_videos_are_written(tmp_path, video, report, where):
    scratch = tmp_path / "scratch"
    with OutputDir(tmp_path / "out") as out:
        files = video_files(out, scratch, video, report)
        stage = out.path("x").parent
    if where is None:
        assert files == {}
    else:
        folder = stage if where == "staged" else scratch
        assert files == {v: folder / f"{v}.mp4" for v in ("demonstration", "execution")}
