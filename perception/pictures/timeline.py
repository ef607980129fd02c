"""The report's timeline: demonstrated (ground truth) against recognized operations.

Two rows of bars on one time axis, one bar per operation coloured by its name
(the names come from the data, i.e. from the rules). Every bar carries an SVG
``<title>`` (the browser's tooltip) and a ``data-info`` line the page shows on
hover; a bar wide enough for its name is also labelled. The legend maps each
colour to its operation.
"""

from __future__ import annotations

from typing import Any

from perception.pictures.svgkit import colors, esc, legend, text_fits, time_ticks

ROW_H, LABEL_W, PX_PER_S, TICK_S = 26, 110, 8.0, 10
ROWS = (("ground truth", "truth"), ("recognized", "recognized"))


def _name(op: dict[str, Any]) -> str:
    """An operation's name; an unclassified motion shows as '?'."""
    return op.get("operation") or "?"


def _span(op: dict[str, Any], t_max: float) -> tuple[float, float]:
    """(start, end) in s; an operation still open at the end runs to ``t_max``."""
    t0 = float(op.get("t_start") or 0.0)
    return t0, float(op["t_end"]) if op.get("t_end") is not None else t_max


def operation_colors(*rows: list[dict[str, Any]]) -> dict[str, str]:
    """One colour per operation name over all rows (shared with the motion plot)."""
    return colors(_name(o) for row in rows for o in row)


def timeline_svg(truth: list[dict[str, Any]], ops: list[dict[str, Any]]) -> str:
    """Two rows of time bars: the ground truth and the recognized operations."""
    rows = [(label, css, items) for (label, css), items in zip(ROWS, (truth, ops), strict=True)]
    t_max = max((float(o["t_end"]) for r in (truth, ops) for o in r
                 if o.get("t_end") is not None), default=1.0)
    width = LABEL_W + int(t_max * PX_PER_S) + 20
    height = ROW_H * 2 + 30
    palette = operation_colors(truth, ops)
    out = [f'<svg id="timeline" xmlns="http://www.w3.org/2000/svg" width="{width}" '
           f'height="{height}" viewBox="0 0 {width} {height}" font-family="monospace" '
           'font-size="10">']
    for k, (label, css, items) in enumerate(rows):
        y = 4 + k * (ROW_H + 4)
        out.append(f'<text x="4" y="{y + 17}" font-size="12">{label}</text>')
        for i, o in enumerate(items):
            t0, t1 = _span(o, t_max)
            x, w = LABEL_W + t0 * PX_PER_S, max(1.0, (t1 - t0) * PX_PER_S)
            name = _name(o)
            info = f"{label} #{i + 1}: {name}, {t0:.2f}-{t1:.2f} s"
            out.append(f'<g class="op {css}" data-name="{esc(name)}" data-info="{esc(info)}">'
                       f'<title>{esc(info)}</title><rect x="{x:.1f}" y="{y}" width="{w:.1f}" '
                       f'height="{ROW_H}" fill="{palette[name]}" stroke="white"/>')
            if text_fits(name, w):
                out.append(f'<text x="{x + 2:.1f}" y="{y + 16}" fill="white">{esc(name)}</text>')
            out.append("</g>")
    out.extend(time_ticks(t_max, LABEL_W, PX_PER_S, 2 * ROW_H + 10, TICK_S))
    out.append("</svg>")
    return "\n".join(out)


def timeline_legend(truth: list[dict[str, Any]], ops: list[dict[str, Any]]) -> str:
    """The colour key of ``timeline_svg`` (operations in order of first appearance)."""
    palette = operation_colors(truth, ops)
    seen = dict.fromkeys(_name(o) for row in (truth, ops) for o in row)
    return legend([(n, palette[n]) for n in seen], "timeline-legend", "operations:")
