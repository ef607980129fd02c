"""execution.json as HTML tables: the verdict, the final state and the monitoring record.

design.md fixes the keys: ``success``, ``failure``, ``verification`` (a bool, or
``{cameras, ground_truth}``), ``mismatches``, ``monitor.detections`` and
``monitor.repairs``; lbw execute adds ``stage``, ``commands``, ``via``, ``robot``,
``expected`` (relations and positions) and the measured ``relations`` and
``positions``. Any of them may be absent (an older file, a run that stopped
early); a table is then left out or says so, and keys nobody expected are
shown in a last table rather than dropped.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from perception.pictures.svgkit import esc

SHOWN = {"success", "failure", "verification", "mismatches", "monitor", "stage", "commands",
         "via", "robot", "expected", "relations", "positions", "final_state_source",
         "initial_state", "recognition", "seconds", "ticks"}


def cell(value: Any) -> str:
    """One value as table-cell HTML: verdicts coloured, vectors as (x, y, z), dicts as k: v."""
    if isinstance(value, bool):
        return f'<span class="{"ok" if value else "bad"}">{"✓ yes" if value else "✗ no"}</span>'
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, Sequence) and not isinstance(value, str):
        if all(isinstance(v, int | float) and not isinstance(v, bool) for v in value):
            return "(" + ", ".join(f"{v:g}" for v in value) + ")"
        return ", ".join(cell(v) for v in value)
    if isinstance(value, Mapping):
        return "<br>".join(f"{esc(k)}: {cell(v)}" for k, v in value.items())
    return esc(value)


def table(rows: Sequence[Mapping[str, Any]], ident: str, columns: Sequence[str] = ()) -> str:
    """Rows of dicts as one table; columns in the given order, then any others seen."""
    cols = list(dict.fromkeys([*columns, *(k for r in rows for k in r)]))
    head = "".join(f"<th>{esc(c)}</th>" for c in cols)
    body = "".join("<tr>" + "".join(f"<td>{cell(r.get(c))}</td>" for c in cols) + "</tr>"
                   for r in rows)
    return f'<table class="grid" id="{esc(ident)}"><tr>{head}</tr>{body}</table>'


def verdict_rows(report: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The verdict as (check, result) rows; ``verification`` may be a bool or a dict."""
    rows = [{"check": "success (the cameras' verdict)", "result": bool(report.get("success"))}]
    checks = report.get("verification")
    if isinstance(checks, Mapping):
        rows += [{"check": f"verification: {k}", "result": v} for k, v in checks.items()]
    elif checks is not None:
        rows.append({"check": "verification", "result": checks})
    for key in ("failure", "stage", "via", "commands", "ticks", "final_state_source"):
        if key in report:
            rows.append({"check": key, "result": report[key]})
    for key, value in (report.get("robot") or {}).items():
        rows.append({"check": f"robot: {key}", "result": value})
    return rows


def position_rows(report: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Per plan object: expected and measured final position, and how far apart (mm)."""
    expected = (report.get("expected") or {}).get("positions") or {}
    measured = report.get("positions") or {}
    rows = []
    for name in sorted(set(expected) | set(measured)):
        e, m = expected.get(name), measured.get(name)
        dist = round(math.dist(e, m), 1) if e is not None and m is not None else None
        rows.append({"object": name, "expected": e, "measured": m, "distance mm": dist})
    return rows


def relation_rows(report: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Expected support relations, each marked as measured too or not."""
    expected = [tuple(_key(r)) for r in (report.get("expected") or {}).get("relations") or []]
    measured = [tuple(_key(r)) for r in report.get("relations") or []]
    rows = [{"relation": " ".join(r), "expected": True, "measured": r in measured}
            for r in expected]
    rows += [{"relation": " ".join(r), "expected": False, "measured": True}
             for r in measured if r not in expected]
    return rows


def _key(relation: Sequence[Any]) -> list[str]:
    """A relation [type, subject, object(s)] as words (a list of supports joined by '+')."""
    return [r if isinstance(r, str) else "+".join(map(str, r)) for r in relation[:3]]


def monitor_html(report: Mapping[str, Any]) -> str:
    """The monitoring record (Sec. IX-C): detections and repairs, or why there is none."""
    monitor = report.get("monitor")
    if not isinstance(monitor, Mapping):
        return '<p id="monitor-none">no monitoring record in execution.json</p>'
    parts = []
    for key, columns, empty in (
            ("detections", ("operator", "object", "expected", "observed", "t"),
             "nothing unexpected was seen"),
            ("repairs", ("operator", "commands"), "no repair was needed")):
        rows = monitor.get(key) or []
        parts.append(f"<h4>{key}</h4>" + (table(rows, f"monitor-{key}", columns) if rows
                                           else f'<p id="monitor-{key}">{empty}</p>'))
    return "".join(parts)


def execution_tables(report: Mapping[str, Any]) -> str:
    """The verdict, mismatches, positions, relations, monitor and any other keys."""
    parts = ["<h3>Verdict</h3>", table(verdict_rows(report), "verdict", ("check", "result"))]
    mism = report.get("mismatches") or []
    parts.append("<h3>Mismatches</h3>" + (
        table(mism, "mismatches", ("message",)) if mism else '<p id="mismatches">none</p>'))
    if report.get("expected") or report.get("positions"):
        parts += ["<h3>Final positions</h3>", table(position_rows(report), "positions"),
                  "<h3>Final relations</h3>", table(relation_rows(report), "relations")]
    parts += ["<h3>Monitoring</h3>", monitor_html(report)]
    rest = {k: v for k, v in report.items() if k not in SHOWN}
    if rest:
        parts += ["<h3>Other</h3>", table([{"key": k, "value": v} for k, v in rest.items()],
                                          "other")]
    return "\n".join(parts)
