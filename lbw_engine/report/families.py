"""``lbw bench`` figures per scenario family: which class of layout fails, at which noise.

Per family and noise level: scenario count, and the exact-sequence, plan-correct
and execution-success rates with their 95% Wilson intervals (``metrics.wilson``);
a crashed scenario counts as a failure of all three. Records written before
families existed have no ``family`` key: they are the classic family.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from lbw_engine.report.metrics import wilson

# figure -> record key: the three rates of the per-family table
RATES = {"exact": "exact", "plan": "plan_correct", "exec": "execution_success"}


def summarize_families(records: list[dict[str, Any]], levels: Sequence[str]
                       ) -> dict[str, dict[str, dict[str, Any]]]:
    """{family: {level: {"n", "crashed", RATE: [successes, lo, hi]}}}, families in order of
    first appearance, levels in the given order (only those with records)."""
    fams: list[str] = []
    for r in records:
        if r.get("family", "classic") not in fams:
            fams.append(r.get("family", "classic"))
    out: dict[str, dict[str, dict[str, Any]]] = {}
    for fam in fams:
        out[fam] = {}
        for level in (*levels, "all"):
            rs = [r for r in records if r.get("family", "classic") == fam and
                  (level == "all" or r["level"] == level)]
            if not rs:
                continue
            row: dict[str, Any] = {"n": len(rs), "crashed": sum("error" in r for r in rs)}
            for figure, key in RATES.items():
                k = sum(1 for r in rs if r.get(key))
                row[figure] = [k, *wilson(k, len(rs))]
            out[fam][level] = row
    return out


def _cell(row: dict[str, Any], figure: str) -> str:
    """``k/n (lo-hi%)``."""
    k, lo, hi = row[figure]
    return f"{k}/{row['n']} ({lo:.0%}-{hi:.0%})"


def format_families(summary: dict[str, dict[str, dict[str, Any]]]) -> str:
    """The per-family figures as a plain text table, one row per family and level."""
    rows = [("family", "level", "n", "exact (95% CI)", "plan ok (95% CI)", "exec ok (95% CI)",
             "crashed")]
    for fam, levels in summary.items():
        for level, row in levels.items():
            rows.append((fam, level, str(row["n"]), _cell(row, "exact"), _cell(row, "plan"),
                         _cell(row, "exec"), str(row["crashed"])))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.ljust(w) if i < 2 else c.rjust(w)
                               for i, (c, w) in enumerate(zip(r, widths, strict=True)))
                     for r in rows)


def markdown_families(summary: dict[str, dict[str, dict[str, Any]]]) -> str:
    """The same table in Markdown (docs/benchmarks.md)."""
    lines = ["| family | level | n | exact (95% CI) | plan ok (95% CI) | exec ok (95% CI) | "
             "crashed |", "|---|---|---|---|---|---|---|"]
    for fam, levels in summary.items():
        for level, row in levels.items():
            lines.append(f"| {fam} | {level} | {row['n']} | {_cell(row, 'exact')} | "
                         f"{_cell(row, 'plan')} | {_cell(row, 'exec')} | {row['crashed']} |")
    return "\n".join(lines)
