"""`lbw run` on every bundled scenario: recognition exact, plan as expected,
execution verified (issue #6 "done when"), and `lbw demo` shows it."""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = sorted(p.stem for p in (ROOT / "scenarios").glob("*.yaml"))
FILES = {"actions.json", "plan.json", "plan.txt", "commands.txt", "execution.json"}


@pytest.fixture(scope="module", params=SCENARIOS)
def run_dir(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param)
    code = main(["run", str(ROOT / "scenarios" / f"{request.param}.yaml"), "--out", str(out)])
    return request.param, code, out


def test_run_succeeds_and_writes_every_file(run_dir):
    name, code, out = run_dir
    assert code == 0, (out / "execution.json").read_text()
    assert FILES <= {p.name for p in out.iterdir()}
    verdict = json.loads((out / "execution.json").read_text())
    assert verdict["success"] is True and verdict["mismatches"] == []


def test_recognition_is_exact(run_dir):
    _, _, out = run_dir
    rec = json.loads((out / "execution.json").read_text())["recognition"]
    assert rec["recognized"] == rec["expected"]


def test_plan_is_one_build_over_every_placed_object(run_dir):
    _, _, out = run_dir
    plan = json.loads((out / "plan.json").read_text())
    root = plan["operators"][plan["root"]]
    actions = json.loads((out / "actions.json").read_text())
    placed = {op["special"][0] for op in actions["operations"] if op["special"]
              and op["operation"].startswith("PLACE")}
    assert root["class"] == "BUILD"
    assert placed <= set(root["base"]) | set(root["target"])


def test_build_table_matches_fig22_and_sec8(tmp_path):
    assert main(["run", str(ROOT / "scenarios" / "build-table.yaml"), "--out", str(tmp_path)]) == 0
    plan = json.loads((tmp_path / "plan.json").read_text())
    ops = plan["operators"]
    root = ops[plan["root"]]
    # Fig. 22: root = ($sequence BUILD-of-legs ACHIEVE-of-plate)
    assert root["plot"][0] == "$sequence" and len(root["plot"]) == 3
    legs, plate = (ops[p[1]] for p in root["plot"][1:])
    assert legs["class"] == "BUILD" and legs["plot"][0] == "$parallel"
    assert len(legs["plot"]) == 5 and all(ops[p[1]]["class"] == "ACHIEVE" for p in legs["plot"][1:])
    assert plate["class"] == "ACHIEVE" and len(plate["target"]) == 4
    assert legs["target"] == ["table"] and len(legs["base"]) == 4
    verdict = json.loads((tmp_path / "execution.json").read_text())
    assert verdict["commands"] == 45  # Sec. VIII: forty-five manipulator commands


def test_demo_shows_the_paper_figures(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "Recognized 21 operations (Fig. 20), exactly as demonstrated" in out
    assert "reach pick reach-with-obj place-on-table" in out
    assert "top two levels (Fig. 22)" in out and "$parallel" in out
    assert "45 manipulator commands" in out and "Verdict: SUCCESS" in out


@pytest.mark.heavy
def test_run_with_video_and_report_adds_the_pictures(tmp_path):
    # the shortest bundled demonstration: encoding its videos is most of this test's time
    code = main(["run", str(ROOT / "scenarios" / "unstack.yaml"), "--out", str(tmp_path),
                 "--video", "--report"])
    assert code == 0
    names = {p.name for p in tmp_path.iterdir()}
    assert FILES | {"demonstration.mp4", "execution.mp4", "plan.svg", "plan.png",
                    "report.html"} <= names
    assert not [n for n in names if n.startswith(".lbw-staging")]
    html = (tmp_path / "report.html").read_text()
    assert "<svg" in html and "achieve" in html


def test_inverted_arch_learned_from_images_matches_fig17_and_fig14(tmp_path):
    assert main(["run", str(ROOT / "scenarios" / "inverted-arch.yaml"),
                 "--out", str(tmp_path)]) == 0
    plan = json.loads((tmp_path / "plan.json").read_text())
    ops = plan["operators"]

    def kids(name):
        return [p[1] for p in ops[name]["plot"][1:]]

    root = ops[plan["root"]]
    assert root["plot"][0] == "$sequence"
    pillar, rest = kids(plan["root"])  # Fig. 17: build03 = seq(achieve01, build02)
    assert ops[pillar]["class"] == "ACHIEVE" and ops[pillar]["base"] == ["pillar"]
    assert ops[rest]["plot"][0] == "$sequence"
    bricks, plank = kids(rest)  # build02 = seq(build01, pachieve01)
    assert ops[bricks]["plot"][0] == "$parallel" and len(kids(bricks)) == 2
    pach = ops[plank]  # Fig. 14: the plank carried with both bricks, their relations kept
    assert pach["class"] == "PACHIEVE"
    assert pach["base"] == ["plank"] and pach["target"] == ["pillar"]
    assert pach["special"] == ["brick-a", "brick-b"]
    assert sorted(r[1] for r in pach["sp"]) == ["brick-a", "brick-b"]
