"""lbw bench --faults: the issue's figures from per-run records (issue #13)."""

import pytest

from lbw_engine.cli.bench_faults import format_faults, summarize_faults


def run(kind, faults, success, detections=(), repairable=True, failure=None,
        cams=True, truth=True, seed=1, executable=True):
    return {"seed": seed, "level": "nominal", "kind": kind, "faults": list(faults),
            "success": success, "detections": list(detections), "repairable": repairable,
            "failure": failure, "verification": {"cameras": cams, "ground_truth": truth},
            "plan_executable": executable}


def fault(kind, detected, relevant=True):
    return {"kind": kind, "t": 5.0, "detected": detected, "relevant": relevant}


RECORDS = [
    run("none", [], True),
    run("none", [], True, detections=[{"t": 3.0}]),
    run("drop", [fault("drop", True)], True, [{"t": 6.0}]),
    run("displace", [fault("displace", False, relevant=False)], True),
    run("remove", [fault("remove", True)], False, [{"t": 6.0}], repairable=False,
        failure="execution: 'p' (shape plate) is gone and the workspace has no spare plate "
                "to replace it", cams=False, truth=False),
    run("drop+displace", [fault("drop", True), fault("displace", False)], False, [{"t": 6.0}],
        failure="verification: ...", cams=False, truth=True),
    {"seed": 2, "level": "nominal", "kind": "none", "error": "boom"},
    # analysis refused the recognized sequence: a recognition failure, not a crash
    {"seed": 4, "level": "2x", "kind": "none", "no_plan": "the demonstration did not give a plan"},
    # a plan learned wrong (it fails without faults, unmonitored too): the monitor rightly
    # detects its wrong structure; its runs measure the recognizer and are counted apart
    run("none", [], False, [{"t": 3.0}], failure="execution: ...", seed=3, executable=False),
    run("drop", [fault("drop", True)], False, [{"t": 6.0}], failure="execution: ...", seed=3,
        executable=False),
]


def test_figures():
    s = summarize_faults(RECORDS)
    assert (s["runs"], s["crashed"], s["no_plan"], s["plans_not_executable"]) == (10, 1, 1, 1)
    assert (s["fault_free_without_detection"], s["fault_free_runs"]) == (1, 2)
    assert (s["faults_detected"], s["faults_injected"]) == (3, 4)
    assert s["faults_on_unused_objects"] == 1
    assert (s["faulty_runs"], s["repairable_runs"], s["repairable_repaired"]) == (3, 2, 1)
    assert (s["unrepaired_runs"], s["unrepaired_with_reason"]) == (2, 2)
    assert (s["verdicts_agree"], s["verdict_runs"]) == (5, 6)
    text = format_faults(s)
    assert "faults detected:                3/4 (75%) (+1 on objects the plan does not use)" in text
    assert "cameras agree with the truth:   5/6 (83%)" in text
    assert "runs: 10, crashed: 1, scenarios that gave no plan: 1, plans that fail" in text


@pytest.mark.parametrize("fault, must", [
    pytest.param({"kind": "drop"}, True, id="a drop"),
    pytest.param({"kind": "remove", "object": "x-a"}, True, id="a remove of a used object"),
    pytest.param({"kind": "remove", "object": "x-other"}, False, id="a remove of an unused one"),
    pytest.param({"kind": "displace", "object": "x-a", "moved_mm": 9.0}, True,
                 id="a displace past the tolerance"),
    pytest.param({"kind": "displace", "object": "x-a", "moved_mm": 3.1}, False,
                 id="a nudge stopped by a neighbour after 3 mm"),
])
def test_which_faults_must_be_detected(fault, must):
    from lbw_engine.cli.bench_faults import counts

    assert counts(fault, {"x-a"}) is must
