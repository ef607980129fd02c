"""report.html's execution timeline: the ACHIEVEs, and the monitor's detections and repairs."""

from perception.pictures.exectimeline import execution_timeline_svg

MONITOR = {
    "detections": [{"operator": "achieve01", "object": "top1", "expected": [95.1, 148.9, 25.0],
                    "observed": [102.5, 177.4, 25.9], "t": 13.17, "kind": "position"}],
    "repairs": [{"operator": "achieve01", "commands": 9, "t": 13.17}],
    "units": [{"operator": "achieve01", "t_start": 0.5, "t_end": 13.17},
              {"operator": "achieve01", "t_start": 13.17, "t_end": 25.78}],
}


def test_units_detections_and_repairs_are_drawn_with_tooltips():
    svg = execution_timeline_svg(MONITOR)
    assert svg.startswith('<svg id="execution-timeline"')
    assert svg.count('<g class="unit"') == 2 and svg.count('<g class="detection"') == 1
    assert svg.count('<g class="repair"') == 1
    assert "<title>detected after achieve01: top1 expected [95.1, 148.9, 25.0], seen " \
           "[102.5, 177.4, 25.9]</title>" in svg
    assert "<title>achieve01, 13.17-25.78 s</title>" in svg
    x_detect = 110 + 13.17 * 6.0  # the mark sits at its time on the robot's clock
    assert f'x1="{x_detect:.1f}"' in svg


def test_no_units_no_timeline():
    assert execution_timeline_svg({"detections": [], "repairs": []}) == ""
