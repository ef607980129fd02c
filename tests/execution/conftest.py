"""Shared helpers for the execution tests."""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main

DATA = Path(__file__).resolve().parent / "data"


@pytest.fixture
def execute_data(tmp_path, capsys):
    """``lbw execute`` of data/NAME.plan.json on data/NAME.yaml (or on ``scenario``):
    the exit code, execution.json and stderr."""
    def run(name, scenario=None):
        out = tmp_path / "out"
        scenario = scenario or DATA / f"{name}.yaml"
        code = main(["execute", str(DATA / f"{name}.plan.json"), str(scenario),
                     "--out", str(out)])
        err = capsys.readouterr().err
        return code, json.loads((out / "execution.json").read_text()), err
    return run
