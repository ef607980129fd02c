"""The execution timeline of report.html: the robot's ACHIEVEs, with what the monitor saw.

One row of bars on the robot's clock, one per ACHIEVE executed (execution.json
``monitor.units``; a repaired ACHIEVE appears again where it was redone), a red
mark at each detection and an orange one at each repair (Sec. IX-C2). Marks and
bars carry ``<title>`` tooltips.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from perception.pictures.svgkit import esc, text_fits, time_ticks

ROW_H, LABEL_W, PX_PER_S, TICK_S = 26, 110, 6.0, 10
DETECT_COLOR, REPAIR_COLOR, UNIT_COLOR = "#d62728", "#ff7f0e", "#4c72b0"


def execution_timeline_svg(monitor: Mapping[str, Any]) -> str:
    """The ACHIEVE bars with detection and repair marks (empty string without units)."""
    units = monitor.get("units") or []
    if not units:
        return ""
    marks = [(d["t"], DETECT_COLOR, "detection",
              f"detected after {d['operator']}: {d['object']} expected {d['expected']}, "
              f"seen {d['observed']}") for d in monitor.get("detections") or []]
    marks += [(r["t"], REPAIR_COLOR, "repair", f"repair: {r['operator']} again, "
               f"{r['commands']} commands") for r in monitor.get("repairs") or [] if "t" in r]
    t_max = max([u["t_end"] for u in units] + [m[0] for m in marks])
    width = LABEL_W + int(t_max * PX_PER_S) + 20
    height = ROW_H * 2 + 34
    out = [f'<svg id="execution-timeline" xmlns="http://www.w3.org/2000/svg" width="{width}" '
           f'height="{height}" viewBox="0 0 {width} {height}" font-family="monospace" '
           'font-size="10">', '<text x="4" y="21" font-size="12">robot</text>']
    for u in units:
        x, w = LABEL_W + u["t_start"] * PX_PER_S, max(1.0, (u["t_end"] - u["t_start"]) * PX_PER_S)
        info = f"{u['operator']}, {u['t_start']:.2f}-{u['t_end']:.2f} s"
        out.append(f'<g class="unit" data-info="{esc(info)}"><title>{esc(info)}</title>'
                   f'<rect x="{x:.1f}" y="4" width="{w:.1f}" height="{ROW_H}" '
                   f'fill="{UNIT_COLOR}" stroke="white"/>')
        if text_fits(u["operator"], w):
            out.append(f'<text x="{x + 2:.1f}" y="20" fill="white">{esc(u["operator"])}</text>')
        out.append("</g>")
    out.append(f'<text x="4" y="{ROW_H + 25}" font-size="12">monitor</text>')
    for t, color, css, info in marks:
        x = LABEL_W + t * PX_PER_S
        out.append(f'<g class="{css}" data-info="{esc(info)}"><title>{esc(info)}</title>'
                   f'<line x1="{x:.1f}" y1="{ROW_H + 8}" x2="{x:.1f}" y2="{2 * ROW_H + 6}" '
                   f'stroke="{color}" stroke-width="3"/></g>')
    out.extend(time_ticks(t_max, LABEL_W, PX_PER_S, 2 * ROW_H + 12, TICK_S))
    out.append("</svg>")
    return "\n".join(out)
