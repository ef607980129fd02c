"""A plan that gives an operation no goal is a failed task (exit 1), not bad input."""

import json
from pathlib import Path

from lbw_engine.cli import main
from lbw_engine.do import plan as planmod
from lbw_engine.paths import bundled_scenario
from lbw_engine.pipeline.execute import execute_plan
from lbw_engine.rules import load_rules
from perception.world.scenario import load

DATA = Path(__file__).resolve().parents[1] / "data"


def _goalless(tmp_path: Path) -> Path:
    doc = json.loads((DATA / "build-table.plan.json").read_text())
    put = next(n for n, op in doc["operators"].items() if op["class"] == "PUT")
    doc["operators"][put]["sc_plus"] = []  # no taught placement left for this PUT
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(doc))
    return path


def test_missing_goal_fails_the_task(tmp_path):
    plan = planmod.load(_goalless(tmp_path))
    result = execute_plan(plan, load(bundled_scenario("build-table")), load_rules())
    assert not result.success
    assert "none of its goal sources" in result.message
    assert result.report["stage"] == "instantiation"
    assert result.report["verification"] == {"cameras": False, "ground_truth": False}


def test_cli_exit_code_is_one(tmp_path, capsys):
    code = main(["execute", str(_goalless(tmp_path)), str(bundled_scenario("build-table")),
                 "--out", str(tmp_path / "out")])
    assert code == 1
    assert "none of its goal sources" in capsys.readouterr().err
    assert json.loads((tmp_path / "out" / "execution.json").read_text())["success"] is False
