"""Parsing of the recognition rule files (Tables III-VIII, Sec. V-B4) into typed records.

Each reader checks the shape of its file (unknown keys, wrong types, names
that are not declared earlier in the same file, numbers out of range) and
duplicate rows; checks that span files are in ``lbw_engine.rules.check``.
"""

from __future__ import annotations

from itertools import product
from pathlib import Path
from typing import Any

from lbw_engine.rules import records as R
from lbw_engine.rules.effects import read_effects
from lbw_engine.rules.reader import Reader
from lbw_engine.yamlio import line_of

ENV_CLASSES = ("World", "HandLoc", "Loc", "Table")  # Fig. 8


def _top(directory: Path, name: str, required: tuple[str, ...], optional=()) -> tuple[Reader, dict]:
    """Load one rule file and check its top-level keys."""
    return Reader.load(directory / name, required, optional)


def _binding(reader: Reader, row: dict, key: str, default: str | None = "none") -> R.Binding:
    """A slot binding: one name of the closed vocabulary, or a list of them."""
    value = row.get(key, default)
    names = value if isinstance(value, list) else [value]
    if not names:
        reader.fail(f"binding {key!r} is an empty list", row, key)
    for name in names:
        reader.one_of(name, R.BINDINGS, f"binding {key!r}:", row, key)
    return tuple(names)


def _events(directory: Path):
    reader, data = _top(directory, "events.yaml", ("detectors", "events"))
    detectors: dict[str, R.DetectorDef] = {}
    for name, spec in reader.mapping(data["detectors"], "detectors", data, "detectors").items():
        spec = reader.mapping(spec, f"detector {name!r}", data["detectors"], name)
        reader.keys(spec, f"detector {name!r}", (), ("builtin",))
        builtin = spec.get("builtin")
        if builtin is not None:
            reader.one_of(builtin, ("constant",), "builtin detector", spec, "builtin")
        detectors[name] = R.DetectorDef(
            name, builtin, R.Where(reader.file, line_of(data["detectors"], name))
        )
    events: dict[str, R.EventDef] = {}
    table = reader.mapping(data["events"], "events", data, "events")
    for key, spec in table.items():
        if isinstance(key, bool):
            reader.fail("an event name reads as a boolean; quote the name", table, key)
        spec = reader.mapping(spec, f"event {key!r}", table, key)
        reader.keys(spec, f"event {key!r}", ("detector", "method", "nodes"), ("meaning",))
        detector = reader.one_of(spec["detector"], detectors, "detector", spec, "detector")
        method = reader.name(spec, "method", f"event {key!r}")
        nodes = reader.sequence(spec["nodes"], "nodes", spec, "nodes")
        for node in nodes:
            reader.one_of(node, ENV_CLASSES, "ENV-node class", spec, "nodes")
        at = R.Where(reader.file, line_of(table, key))
        events[key] = R.EventDef(key, str(spec.get("meaning", "")), detector, method,
                                 tuple(nodes), at)
    return detectors, events


def _motion_features(directory: Path, events: dict[str, R.EventDef]) -> R.MotionFeatures:
    reader, data = _top(directory, "motion-features.yaml", ("speed-ranges", "angles", "values"))
    ranges: dict[str, tuple[float, float]] = {}
    table = reader.mapping(data["speed-ranges"], "speed-ranges", data, "speed-ranges")
    for event, spec in table.items():
        reader.one_of(event, events, "event", table, event)
        spec = reader.mapping(spec, f"speed range {event!r}", table, event)
        reader.keys(spec, f"speed range {event!r}", ("low", "high"))
        low = reader.number(spec, "low", "speed 'low'", 0.0, 1e5)
        high = reader.number(spec, "high", "speed 'high'", 0.0, 1e5)
        if not 0 <= low < high:
            reader.fail(f"speed range {event!r} needs 0 <= low < high", table, event)
        ranges[event] = (low, high)
    angles = reader.mapping(data["angles"], "angles", data, "angles")
    reader.keys(angles, "angles", ("down", "up"))
    down = reader.number(angles, "down", "angle 'down'", 0.0, 180.0)
    up = reader.number(angles, "up", "angle 'up'", 0.0, 180.0)
    if not 0 < down < up < 180:
        reader.fail("angles need 0 < down < up < 180 degrees", data, "angles")
    rows: list[R.FeatureValueRow] = []
    seen: dict[Any, int] = {}
    values = reader.sequence(data["values"], "values", data, "values")
    for index, row in enumerate(values):
        row = reader.mapping(row, "a value row", values, index)
        reader.keys(row, "a value row", ("value", "speed"), ("direction",))
        value = reader.name(row, "value", "value row")
        speed = reader.one_of(row["speed"], R.SPEED_TESTS, "speed test", row, "speed")
        direction = row.get("direction")
        if speed == "within":
            reader.one_of(direction, R.DIRECTION_TESTS, "direction test", row, "direction")
        elif direction is not None:
            reader.fail(f"a {speed!r} row cannot test the direction (Table IV)", row, "direction")
        sig = (speed, direction)
        if sig in seen or value in [r.value for r in rows]:
            reader.fail(f"duplicate row for {value!r}: it can never fire", values, index)
        seen[sig] = index
        rows.append(
            R.FeatureValueRow(value, speed, direction, R.Where(reader.file, line_of(values, index)))
        )
    needed = {("slow", None), ("fast", None)} | {("within", d) for d in R.DIRECTION_TESTS}
    missing = needed - set(seen)
    if missing:
        reader.fail(f"Table IV rows do not cover {sorted(map(str, missing))}", data, "values")
    return R.MotionFeatures(ranges, down, up, tuple(rows))


def _motions(directory: Path) -> dict[str, R.MotionClass]:
    reader, data = _top(directory, "motions.yaml", ("motions",))
    table = reader.mapping(data["motions"], "motions", data, "motions")
    motions: dict[str, R.MotionClass] = {}
    for name, spec in table.items():
        spec = reader.mapping(spec, f"motion {name!r}", table, name)
        reader.keys(spec, f"motion {name!r}", ("level",), ("start", "root", "fine"))
        level = spec["level"]
        if isinstance(level, bool) or not isinstance(level, int) or level < 0:
            reader.fail(f"motion {name!r} level must be a whole number >= 0", spec, "level")
        flags = {}
        for flag in ("start", "root", "fine"):
            flags[flag] = spec.get(flag, False)
            if not isinstance(flags[flag], bool):
                reader.fail(f"{flag!r} must be a boolean", spec, flag)
        at = R.Where(reader.file, line_of(table, name))
        motions[name] = R.MotionClass(name, level, flags["start"], flags["root"], flags["fine"], at)
    for flag in ("start", "root"):
        marked = [m for m in motions.values() if getattr(m, flag)]
        if len(marked) != 1:
            reader.fail(f"exactly one motion class must be marked {flag!r}", data, "motions")
    return motions


def _operations(directory: Path, events, motions):
    reader, data = _top(directory, "operations.yaml", ("features", "classification"))
    features: dict[str, R.FeatureDef] = {}
    table = reader.mapping(data["features"], "features", data, "features")
    for name, spec in table.items():
        spec = reader.mapping(spec, f"feature {name!r}", table, name)
        reader.keys(spec, f"feature {name!r}", ("source",),
                    ("detector", "values", "kinds", "names"))
        source = reader.one_of(spec["source"], R.FEATURE_SOURCES, "feature source", spec, "source")
        values: tuple[Any, ...] = ()
        kinds: dict[str, str] = {}
        answers: dict[Any, Any] = {}
        detector = names = None
        if source == "snapshot-diff":
            if "detector" not in spec or "values" not in spec:
                reader.fail(f"feature {name!r} needs a detector and its values", table, name)
            detector = reader.name(spec, "detector", f"feature {name!r}")
            answers = _answers(reader, spec, name)
            values = tuple(answers)
            if "names" in spec:
                names = reader.one_of(spec["names"], R.NAMED_SLOTS, f"feature {name!r} names",
                                      spec, "names")
        elif source == "final-event":
            values = tuple(events)
        elif source == "hand-holds":
            values = (True, False)
        else:
            kinds = dict(reader.mapping(spec.get("kinds"), "kinds", spec, "kinds"))
            for kind in kinds:
                reader.one_of(kind, ENV_CLASSES, "ENV-node class", spec, "kinds")
            values = tuple(kinds.values())
        takes = {
            "snapshot-diff": ("detector", "values", "names"),
            "target-kind": ("kinds",),
            "support-kind": ("kinds",),
        }
        for key in ("detector", "values", "kinds", "names"):
            if key in spec and key not in takes.get(source, ()):
                reader.fail(f"feature {name!r} of source {source!r} takes no {key!r}", spec, key)
        at = R.Where(reader.file, line_of(table, name))
        features[name] = R.FeatureDef(name, source, detector, values, kinds, at, answers,
                                        names)
    classification: dict[str, tuple[R.ClassRow, ...]] = {}
    table = reader.mapping(data["classification"], "classification", data, "classification")
    for motion, rows in table.items():
        reader.one_of(motion, motions, "motion class", table, motion)
        rows = reader.sequence(rows, f"rows of {motion}", table, motion)
        out: list[R.ClassRow] = []
        for index, row in enumerate(rows):
            row = reader.mapping(row, "a Table V row", rows, index)
            reader.keys(row, "a Table V row", ("operation",), ("when", "label"))
            operation = reader.name(row, "operation", "Table V row")
            when = reader.mapping(row.get("when", {}), "when", row, "when")
            for feature, value in when.items():
                spec = reader.one_of(feature, features, "feature", when, feature)
                reader.one_of(value, features[spec].values, f"value of {feature!r}:", when, feature)
            at = R.Where(reader.file, line_of(rows, index))
            for earlier in out:
                if earlier.when.items() <= when.items():
                    raise at.error(
                        f"this {motion} row can never fire: the row at line "
                        f"{earlier.at.line} already matches whenever it does"
                    )
            label = reader.name(row, "label", "Table V row") if "label" in row else None
            out.append(R.ClassRow(motion, dict(when), operation, at, label))
        _covered(motion, out, features, R.Where(reader.file, line_of(table, motion)))
        classification[motion] = tuple(out)
    return features, classification


def _covered(motion: str, rows: list, features: dict, at: R.Where) -> None:
    """Every motion of the class gets an operation: an Other row (no ``when``), or a row
    for each combination of the values its rows ask about (round 15: a class of local
    motions without its no-change row classified an unchanged snapshot as nothing)."""
    if any(not r.when for r in rows):
        return
    asked = sorted({f for r in rows for f in r.when})
    for combo in product(*(features[f].values for f in asked)):
        case = dict(zip(asked, combo, strict=True))
        if not any(all(case[f] == v for f, v in r.when.items()) for r in rows):
            shown = ", ".join(f"{f}: {str(v).lower() if isinstance(v, bool) else v}"
                              for f, v in case.items())
            raise at.error(f"no {motion} row matches {{{shown}}}: add one, or an Other row "
                           "(a row without 'when')")


def _answers(reader: Reader, spec: dict, name: str) -> dict[Any, Any]:
    """A snapshot-diff feature's values: feature value -> the detector's answer."""
    table = reader.mapping(spec["values"], f"values of feature {name!r} (value: answer)",
                           spec, "values")
    seen: dict[Any, Any] = {}
    for value, answer in table.items():
        if isinstance(value, bool) or not isinstance(value, str | int):
            reader.fail(f"feature {name!r}: value {value!r} must be a name", table, value)
        if isinstance(answer, bool) or not isinstance(answer, str | int):
            reader.fail(f"feature {name!r}: the detector's answer for {value!r} must be a "
                        "name or a whole number", table, value)
        if answer in seen:
            reader.fail(f"feature {name!r}: {value!r} and {seen[answer]!r} stand for the same "
                        f"answer {answer!r}", table, value)
        seen[answer] = value
    return dict(table)


def _transitions(directory: Path) -> dict[tuple[str, str], R.TransitionRow]:
    reader, data = _top(directory, "transitions.yaml", ("transitions",))
    rows = reader.sequence(data["transitions"], "transitions", data, "transitions")
    out: dict[tuple[str, str], R.TransitionRow] = {}
    for index, row in enumerate(rows):
        row = reader.mapping(row, "a Table VII row", rows, index)
        reader.keys(
            row,
            "a Table VII row",
            ("motion", "event", "transition"),
            ("next", *R.SLOTS, "close-target"),
        )
        motion = reader.name(row, "motion", "Table VII row")
        key = reader.name(row, "event", "Table VII row")
        direction = reader.one_of(row["transition"], R.DIRECTIONS, "transition", row, "transition")
        nxt = reader.name(row, "next", "Table VII row") if row.get("next") is not None else None
        if (direction in ("next", "down")) != (nxt is not None):
            reader.fail(
                f"a {direction!r} transition {'needs' if nxt is None else 'takes no'} 'next'",
                rows,
                index,
            )
        slots = {slot: _binding(reader, row, slot) for slot in R.SLOTS if slot in row}
        close = _binding(reader, row, "close-target") if "close-target" in row else None
        at = R.Where(reader.file, line_of(rows, index))
        if (motion, key) in out:
            first = out[(motion, key)].at.line
            raise at.error(f"duplicate row for {motion} on {key!r} (first at line {first})")
        out[(motion, key)] = R.TransitionRow(motion, key, direction, nxt, slots, close, at)
    return out


def _redirections(directory: Path) -> dict[str, tuple[R.RedirectionRow, ...]]:
    reader, data = _top(directory, "attention.yaml", ("redirections",))
    rows = reader.sequence(data["redirections"], "redirections", data, "redirections")
    out: dict[str, list[R.RedirectionRow]] = {}
    for index, row in enumerate(rows):
        row = reader.mapping(row, "a Table VIII row", rows, index)
        reader.keys(row, "a Table VIII row", ("motion", "on", "op"), ("event", "base", "target"))
        motion = reader.name(row, "motion", "Table VIII row")
        key = reader.name(row, "on", "Table VIII row")
        op = reader.one_of(row["op"], R.STACK_OPS, "stack operation", row, "op")
        event = reader.name(row, "event", "Table VIII row") if "event" in row else None
        if op != "delete" and event is None:
            reader.fail(f"an {op!r} redirection needs the next 'event'", rows, index)
        at = R.Where(reader.file, line_of(rows, index))
        rec = R.RedirectionRow(
            motion,
            key,
            op,
            event,
            _binding(reader, row, "base"),
            _binding(reader, row, "target"),
            at,
        )
        for other in out.get(motion, []):
            if (other.key, other.op, other.event) == (key, op, event):
                raise at.error(
                    f"duplicate row for {motion} on {key!r} (first at line {other.at.line})"
                )
        out.setdefault(motion, []).append(rec)
    return {m: tuple(rs) for m, rs in out.items()}


# constants.yaml: every constant the engine and the detectors read, with its kind and
# the range lbw check enforces (docs/engine.md lists them with their meaning).
CONSTANTS: dict[str, tuple[str, float, float]] = {
    "attention-region": ("sizes", 5.0, 300.0),  # mm, W x D x H
    "search-cycle-limit": ("count", 1, 20),
    "repositioning-distance": ("number", 10.0, 600.0),  # mm
    "motion-detector-interval": ("number", 0.01, 1.0),  # s
    "detect-passes-per-frame": ("count", 1, 64),
    "place-clearance": ("number", 0.0, 20.0),  # mm
    "place-overlap-limit": ("number", 0.0, 50.0),  # mm
    "hand-velocity-window": ("number", 0.05, 2.0),  # s
    "far-margin": ("number", 5.0, 300.0),  # mm
    "align-slide": ("number", 0.0, 100.0),  # mm
    "align-slide-doubt": ("number", 0.0, 50.0),  # mm
}


def _constants(directory: Path) -> dict[str, Any]:
    reader, data = _top(directory, "constants.yaml", tuple(CONSTANTS))
    out: dict[str, Any] = {}
    for key, (kind, low, high) in CONSTANTS.items():
        if kind == "sizes":
            out[key] = reader.vector(data, key, 3, key, low, high)
        elif kind == "count":
            value = data[key]
            if isinstance(value, bool) or not isinstance(value, int):
                reader.fail(f"{key} must be a whole number", data, key)
            out[key] = int(reader.number(data, key, key, low, high))
        else:
            out[key] = reader.number(data, key, key, low, high)
    return out


def read_all(directory: Path) -> R.RuleSet:
    """Parse every rule file of ``directory``."""
    detectors, events = _events(directory)
    motion_features = _motion_features(directory, events)
    motions = _motions(directory)
    features, classification = _operations(directory, events, motions)
    relations, roles, effects = read_effects(directory)
    return R.RuleSet(
        directory=directory,
        detectors=detectors,
        events=events,
        motion_features=motion_features,
        motions=motions,
        features=features,
        classification=classification,
        relations=relations,
        roles=roles,
        effects=effects,
        transitions=_transitions(directory),
        redirections=_redirections(directory),
        constants=_constants(directory),
    )
