"""lbw run's pictures: monitor and execution videos, plan pictures and report.html, staged."""

import xml.etree.ElementTree as ET

import cv2

from lbw_engine.cli.pictures import run_with_pictures
from lbw_engine.outputs import OutputDir
from lbw_engine.pipeline.run import publish
from perception.world.generator import generate


def test_run_with_pictures_stages_every_file(tmp_path):
    sc = generate(5, structures=["tower"]).scenario()
    with OutputDir(tmp_path) as out:
        result = run_with_pictures(sc, None, out, video=True, report=True)
        publish(result, out)
    names = {p.name for p in tmp_path.iterdir()}
    assert {"demonstration.mp4", "execution.mp4", "report.html", "plan.svg", "plan.png",
            "actions.json", "plan.json", "plan.txt", "execution.json"} <= names
    assert result.recognition["exact"] and result.success, result.failure
    for video in ("demonstration.mp4", "execution.mp4"):
        cap = cv2.VideoCapture(str(tmp_path / video))
        assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) > 100, video
        cap.release()
    svg = ET.parse(tmp_path / "plan.svg").getroot()
    boxes = [g for g in svg.iter("{http://www.w3.org/2000/svg}g") if g.get("class") == "operator"]
    assert len(boxes) == len(result.plan["operators"])
    html = (tmp_path / "report.html").read_text()
    assert 'id="timeline"' in html and f'id="op-{result.plan["root"]}"' in html
    assert "verified: the executed structure matches the plan" in html

