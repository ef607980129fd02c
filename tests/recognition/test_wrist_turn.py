"""`lbw run` on a demonstration whose fingers close along y (issue #12, data/wrist-turn.yaml).

The hand-tracker finds the hand by its gray band; with the wrist turned the
fingers' footprint changes (20 mm along x, 10 mm along y each). The run must still
recognize the demonstration exactly, including the north-face ALIGN, and verify.
"""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("wrist-turn")
    return main(["run", str(DATA / "wrist-turn.yaml"), "--out", str(out)]), out


def test_wrist_turn_run_exits_0_exact_and_verified(run):
    code, out = run
    verdict = json.loads((out / "execution.json").read_text())
    assert code == 0, verdict.get("failure")
    assert verdict["success"] is True and verdict["mismatches"] == []
    assert verdict["recognition"]["exact"] is True


def test_wrist_turn_align_is_seen_against_its_neighbour(run):
    _, out = run
    ops = json.loads((out / "actions.json").read_text())["operations"]
    aligned = [op for op in ops if any(f["operation"] == "ALIGN" for f in op.get("fine", []))]
    assert [op["special"] for op in aligned] == [["s2"]]
    assert ["coplanar", "s2", "s1"] in aligned[0]["final_state"]["relations"]
