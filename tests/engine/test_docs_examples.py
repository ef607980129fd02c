"""The example trace in docs/replay-trace.md runs and gives what the page says."""

import re
from pathlib import Path

from lbw_engine.rules import load_rules
from lbw_engine.see.actions import sequence
from lbw_engine.see.replay import recognize_trace

DOC = Path(__file__).resolve().parents[2] / "docs" / "replay-trace.md"


def test_replay_doc_example(tmp_path):
    block = re.search(r"## Example: one pick\n\n```\n(.*?)```", DOC.read_text(), re.S).group(1)
    trace = tmp_path / "example.jsonl"
    trace.write_text(block)
    rec, replay = recognize_trace(trace, load_rules())
    assert sequence(rec) == ["REACH", "PICK", "WITHDRAW"]
    assert replay.unused() == []
    assert "gives REACH, PICK, WITHDRAW" in DOC.read_text()
