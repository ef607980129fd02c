"""`lbw recognize` and `lbw demo`: actions.json in the design.md format, and bad
input (missing file, bad JSON, a bad trace line) as one sentence with exit 2,
no traceback and no output files."""

import json
from pathlib import Path

import pytest

from lbw_engine.cli import main

TRACES = Path(__file__).resolve().parent.parent / "data" / "traces"
HEADER = '{"format": "lbw-event-trace", "version": 1}\n'
OP_KEYS = {"name", "operation", "motion", "t_start", "t_end", "initial_event", "final_event",
           "base", "target", "special", "fine", "initial_state", "final_state"}


def test_recognize_writes_actions_json(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["recognize", str(TRACES / "fig20-build-table.jsonl"), "--out", str(out)]) == 0
    data = json.loads((out / "actions.json").read_text())
    assert set(data) == {"objects", "operations"}
    assert all(set(op) == OP_KEYS for op in data["operations"])
    pick = data["operations"][1]
    assert (pick["name"], pick["operation"], pick["motion"]) == ("pick01", "PICK", "LocalMotion")
    assert pick["target"] == ["brick190"] and pick["special"] == []
    assert ["held-by", "brick190", "hand"] in pick["final_state"]["relations"]
    assert set(pick["initial_state"]) == {"relations", "positions"}
    assert pick["t_start"] < pick["t_end"]
    assert [f["operation"] for f in pick["fine"]] == ["NO-OP"]  # the FineMotion between
    assert "21 operations" in capsys.readouterr().out


BAD = [  # (case id, trace text or None for a missing file, message fragment, line)
    ("missing-file", None, "trace file not found", None),
    ("no-header", '{"t": 0, "event": "near"}\n', "first line must be the header", 1),
    ("bad-json", HEADER + '{"t": 0, "event": \n', "not a JSON object", 2),
    ("not-an-object", HEADER + "[1, 2]\n", "must be a JSON object", 2),
    ("unknown-event", HEADER + '{"t": 0, "event": "nearby"}\n', "event 'nearby' does not", 2),
    ("unknown-key", HEADER + '{"t": 0, "event": "near", "colour": 1}\n', "unknown key", 2),
    ("no-time", HEADER + '{"event": "near"}\n', "needs a time 't'", 2),
    ("time-goes-back", HEADER + '{"t": 2, "event": "far"}\n{"t": 1, "event": "far"}\n',
     "goes back", 3),
    ("bad-vector", HEADER + '{"t": 0, "event": "far", "velocity": [1, 2]}\n', "three numbers", 2),
    ("bad-motion-value", HEADER + '{"t": 0, "event": "small-motion", "value": "wobbly"}\n',
     "not a Table IV motion value", 2),
    ("unknown-detector", HEADER + '{"t": 0, "detector": "x-ray", "value": 1}\n',
     "not a replayable detector", 2),
    ("found-unknown-object", HEADER
     + '{"t": 0, "event": "loc-exist", "found": ["b9"]}\n', "'found' names 'b9'", 2),
    ("empty", "", "no header line", None),
]


@pytest.mark.parametrize("text,message,line", [c[1:] for c in BAD], ids=[c[0] for c in BAD])
def test_bad_trace(tmp_path, capsys, text, message, line):
    trace = tmp_path / "trace.jsonl"
    if text is not None:
        trace.write_text(text)
    out = tmp_path / "out"
    assert main(["recognize", str(trace), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    if line is not None:
        assert f"trace.jsonl:{line}:" in err
    assert not out.exists() or not any(out.iterdir())  # nothing half written


def test_bad_rules_folder(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["recognize", str(TRACES / "fig20-build-table.jsonl"), "--out", str(out),
                 "--rules", str(tmp_path / "missing")])
    assert code == 2 and "rules folder not found" in capsys.readouterr().err
    assert not out.exists()
