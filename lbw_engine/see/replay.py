"""A replay ENV model: detectors that answer event queries from a recorded trace.

The trace format is documented in docs/replay-trace.md: JSON Lines, a header
line, then one record per line, in time order. Each record answers one query
(or one snapshot comparison) at its time; ``frames()`` gives the recognizer
one frame per distinct time.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lbw_engine.errors import InputError
from lbw_engine.guard import json_document, read_text, shorten
from lbw_engine.rules import RuleSet
from lbw_engine.see.detectors import ActView, Detection, ObjectInfo, Query

HEADER = {"format": "lbw-event-trace", "version": 1}
EVENT_KEYS = {"t", "event", "found", "value", "velocity", "positions", "objects", "base"}
DIFF_KEYS = {"t", "detector", "value", "at"}


@dataclass
class Record:
    """One trace line: an event answer or a snapshot-comparison result."""

    line: int
    t: float
    event: str | None
    detector: str | None
    data: dict[str, Any]
    used: bool = False


class Trace:
    """A parsed, checked event trace."""

    def __init__(self, path: str | Path, records: list[Record]) -> None:
        self.path = str(path)
        self.records = records
        self.now: list[Record] = []

    def frames(self) -> list[tuple[float, None]]:
        """One (t, frame) per distinct record time; replay frames carry no image."""
        return [(t, None) for t in sorted({r.t for r in self.records})]

    def begin_frame(self, t: float) -> None:
        """Make the records at time ``t`` current."""
        self.now = [r for r in self.records if r.t == t]

    def take(self, event: str | None, detector: str | None, base: tuple[str, ...]) -> Record | None:
        """The first unused current record for this event (or detector comparison)."""
        for rec in self.now:
            if rec.used or rec.event != event or rec.detector != detector:
                continue
            if "base" in rec.data and tuple(rec.data["base"]) != base:
                continue
            rec.used = True
            return rec
        return None

    def unused(self) -> list[Record]:
        """Records no query asked for (the recognizer was not waiting for them)."""
        return [r for r in self.records if not r.used]

    def error(self, rec: Record, message: str) -> InputError:
        """An InputError at a record's line."""
        return InputError(message, file=self.path, line=rec.line)


class ReplayDetector:
    """The detector called ``name``, answering from ``trace`` (the Detector protocol).

    A trace is written in the rules' own words (events, Table V values); the
    comparison values are turned into this detector's answers through the rules'
    feature tables, so the engine reads them back as it reads any detector's.
    """

    def __init__(self, trace: Trace, name: str, rules: RuleSet) -> None:
        self.trace = trace
        self.name = name
        self._answer = {value: answer for f in rules.features.values() if f.detector == name
                        for value, answer in f.answers.items()}
        self.methods = frozenset(e.method for e in rules.events.values() if e.detector == name)
        self.answers = frozenset(self._answer.values())

    def begin_frame(self, t: float, frame: Any) -> None:
        """Select the trace records at ``t``."""
        self.trace.begin_frame(t)

    def query(self, query: Query, env) -> Detection | None:
        """The current record for the query's event, as a Detection."""
        rec = self.trace.take(query.event, None, tuple(n.name for n in query.base))
        if rec is None:
            return None
        data = rec.data
        objects = {
            name: ObjectInfo(o["shape"], tuple(o["size"]), tuple(o["position"]))
            for name, o in data.get("objects", {}).items()
        }
        known = set(env.nodes) | set(objects)
        for name in data.get("found", []):
            if name not in known:
                raise self.trace.error(
                    rec, f"'found' names {shorten(name)}, which is not a located object"
                )
        return Detection(
            found=tuple(data.get("found", ())),
            value=data.get("value"),
            velocity=tuple(data["velocity"]) if "velocity" in data else None,
            positions={n: tuple(p) for n, p in data.get("positions", {}).items()},
            objects=objects,
        )

    def snapshot(self, act: ActView, env) -> Any:
        """A replay snapshot is just the time it was taken."""
        return act.t

    def compare(self, first: Any, last: Any, act: ActView, env) -> Detection | None:
        """The comparison result recorded for this detector at the current time."""
        rec = self.trace.take(None, self.name, act.base) or self.trace.take(None, self.name, ())
        if rec is None:
            return None
        at = rec.data.get("at")
        value = rec.data.get("value")
        return Detection(value=self._answer.get(value, value) if isinstance(value, str | int)
                         else value, position=tuple(at) if at else None)


def _vec(trace_path, line: int, value: Any, what: str) -> None:
    if (
        not isinstance(value, list)
        or len(value) != 3
        or not all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for v in value
        )
    ):
        raise InputError(f"{what} must be three numbers [x, y, z]", file=trace_path, line=line)


def _check_record(path, line: int, data: dict, rules: RuleSet) -> Record:
    """Check one record against the rules; one clear sentence on the first problem."""

    def bad(message: str) -> InputError:
        return InputError(message, file=path, line=line)

    t = data.get("t")
    if isinstance(t, bool) or not isinstance(t, int | float) or not math.isfinite(t) or t < 0:
        raise bad("every record needs a time 't' in seconds (a number >= 0)")
    if ("event" in data) == ("detector" in data):
        raise bad("a record has either an 'event' or a 'detector' (a snapshot comparison)")
    keys = EVENT_KEYS if "event" in data else DIFF_KEYS
    for key in data:
        if key not in keys:
            raise bad(f"unknown key {shorten(key)} (allowed: {sorted(keys)})")
    if "detector" in data:
        name = data["detector"]
        if not isinstance(name, str) or name not in rules.detectors or \
                rules.detectors[name].builtin:
            raise bad(f"detector {shorten(name)} is not a replayable detector of the rules")
        if "at" in data:
            _vec(path, line, data["at"], "'at'")
        return Record(line, float(t), None, name, data)
    event = data["event"]
    if not isinstance(event, str) or event not in rules.events:
        raise bad(f"event {shorten(event)} does not exist in the rules")
    if "value" in data and event in rules.motion_features.ranges:
        if data["value"] not in rules.motion_features.values():
            raise bad(f"value {shorten(data['value'])} is not a Table IV motion value")
    for key in ("found", "base"):
        if key in data and not (
            isinstance(data[key], list) and all(isinstance(n, str) for n in data[key])
        ):
            raise bad(f"{shorten(key)} must be a list of names")
    if "velocity" in data:
        _vec(path, line, data["velocity"], "'velocity'")
    positions = data.get("positions", {})
    if not isinstance(positions, dict):
        raise bad("'positions' must map names to [x, y, z]")
    for name, pos in positions.items():
        _vec(path, line, pos, f"position of {shorten(name)}")
    objects = data.get("objects", {})
    if not isinstance(objects, dict):
        raise bad("'objects' must map names to {shape, size, position}")
    for name, obj in objects.items():
        if not isinstance(obj, dict) or set(obj) != {"shape", "size", "position"} or \
                not isinstance(obj["shape"], str):
            raise bad(f"object {shorten(name)} needs exactly shape, size and position")
        _vec(path, line, obj["size"], f"size of {shorten(name)}")
        _vec(path, line, obj["position"], f"position of {shorten(name)}")
    return Record(line, float(t), event, None, data)


def load_trace(path: str | Path, rules: RuleSet) -> Trace:
    """Read and check a trace file (docs/replay-trace.md)."""
    path = Path(path)
    text = read_text(path, noun="trace file", expected="a trace file")
    records: list[Record] = []
    header = False
    last = 0.0
    for number, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped or stripped.startswith("#"):
            continue
        try:
            data = json_document(stripped)
        except InputError as exc:
            raise InputError(f"not a JSON object ({exc.message})", file=path,
                             line=number) from None
        if not isinstance(data, dict):
            raise InputError("each line must be a JSON object", file=path, line=number)
        if not header:
            if data != HEADER:
                raise InputError(
                    f"the first line must be the header {json.dumps(HEADER)}",
                    file=path,
                    line=number,
                )
            header = True
            continue
        rec = _check_record(path, number, data, rules)
        if rec.t < last:
            raise InputError(
                f"time {rec.t} goes back (previous record at {last})", file=path, line=number
            )
        last = rec.t
        records.append(rec)
    if not header:
        raise InputError("empty trace: no header line", file=path)
    return Trace(path, records)


def replay_detectors(trace: Trace, rules: RuleSet) -> dict[str, ReplayDetector]:
    """A replay detector for every non-builtin detector the rules name."""
    return {
        name: ReplayDetector(trace, name, rules)
        for name, d in rules.detectors.items() if not d.builtin
    }


def recognize_trace(path: str | Path, rules: RuleSet):
    """Run the recognizer over a trace file; returns (recognizer, trace)."""
    from lbw_engine.see.detectors import DetectorRegistry
    from lbw_engine.see.recognizer import Recognizer

    trace = load_trace(path, rules)
    registry = DetectorRegistry.for_rules(rules, replay_detectors(trace, rules))
    recognizer = Recognizer(rules, registry)
    recognizer.run(trace.frames())
    return recognizer, trace


def script_trace(
    rules: RuleSet, frames: list[list[dict[str, Any]]], name: str = "<script>"
) -> Trace:
    """An in-memory trace: frame i (from 1) holds the records ``frames[i-1]`` (no 't')."""
    records = []
    for index, frame in enumerate(frames, start=1):
        for data in frame:
            records.append(
                _check_record(name, len(records) + 1, {"t": float(index), **data}, rules)
            )
    return Trace(name, records)


def run_script(rules: RuleSet, frames: list[list[dict[str, Any]]]):
    """A recognizer stepped through frame 0 (cold boot) and then one frame per list item.

    The recognizer is left open (``finish`` not called) so tests can look at
    its stack and ACT-nodes; an empty list is a frame in which nothing happens.
    """
    from lbw_engine.see.detectors import DetectorRegistry
    from lbw_engine.see.recognizer import Recognizer

    trace = script_trace(rules, frames)
    recognizer = Recognizer(
        rules, DetectorRegistry.for_rules(rules, replay_detectors(trace, rules))
    )
    recognizer.step(0.0)
    for index in range(1, len(frames) + 1):
        recognizer.step(float(index))
    return recognizer
