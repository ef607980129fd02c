"""The motion-feature plot: the hand's speed and direction over time, and where it was cut.

Table IV turns the tracked hand's velocity into qualitative values: the speed
against the two thresholds V_L, V_H of the range the query selects, the angle
between the velocity and straight down against A_D and A_U (footnote 11).
Table VII then cuts the motion into ACT-nodes at events. The plot puts all of
it on one time axis (``motiontrace.MotionTrace``), top to bottom:

| band      | what                                                                  |
|-----------|-----------------------------------------------------------------------|
| motions   | the top-level ACT-nodes, coloured by operation, and their sub-motions |
| cuts      | each segmentation point, labelled with the events that made it        |
| speed     | hand speed (log scale) with every V_L/V_H of rules/motion-features    |
| angle     | angle from straight down, with A_D and A_U                            |
| height    | hand height z                                                         |
| features  | one lane per speed range: the Table IV value the recognizer got       |
| events    | every other interpreted event, one tick each                          |

Every mark has an SVG ``<title>`` (tooltip). Thresholds and value names come
from the loaded rules, never from this module.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from lbw_engine.rules import MotionFeatures
from perception.pictures.motiontrace import LoggedEvent, MotionTrace, Segment
from perception.pictures.svgkit import colors, esc, legend, text_fits

PX_PER_S, LEFT, RIGHT = 12.0, 118, 200
MOTIONS_Y, CUTS_Y, CUTS_H = 4, 44, 58
SPEED_Y, SPEED_H, ANGLE_Y, ANGLE_H, Z_Y, Z_H = 106, 150, 268, 110, 390, 70
LANE_H, GAP_S, TICK_S = 14, 0.25, 5
CUT_COLOR, THRESHOLD_COLOR = "#333", "#c0392b"


class Scales:
    """Time and value to picture coordinates (one object per plot)."""

    def __init__(self, trace: MotionTrace, features: MotionFeatures) -> None:
        """Fit the time axis to the trace and the speed axis to speeds and thresholds."""
        ends = [trace.t_end] + [s.t_end for s in trace.segments] + [s.t for s in trace.samples]
        self.t_max = max(ends + [1.0])
        top = [s.speed for s in trace.samples] + [v for r in features.ranges.values() for v in r]
        self.decades = max(1, math.ceil(math.log10(max(top + [10.0]))))
        heights = [s.z for s in trace.samples]
        self.z_max = max(50.0, 1.1 * max(heights, default=0.0))
        self.width = LEFT + self.t_max * PX_PER_S + RIGHT

    def x(self, t: float) -> float:
        """Time (s) to x."""
        return LEFT + t * PX_PER_S

    def speed(self, v: float) -> float:
        """Speed (mm/s, log scale from 1 mm/s) to y."""
        return SPEED_Y + SPEED_H * (1.0 - math.log10(max(v, 1.0)) / self.decades)

    def angle(self, a: float) -> float:
        """Angle from straight down (deg; 0 at the bottom, 180 at the top) to y."""
        return ANGLE_Y + ANGLE_H * (1.0 - a / 180.0)

    def z(self, z: float) -> float:
        """Hand height (mm) to y."""
        return Z_Y + Z_H * (1.0 - max(0.0, z) / self.z_max)


def _polylines(trace: MotionTrace, y: Callable[[Any], float | None], x: Callable[[float], float],
               css: str, color: str) -> list[str]:
    """One polyline per tracked stretch (a gap over GAP_S breaks the line)."""
    runs: list[list[str]] = []
    last = -1e9
    for s in trace.samples:
        value = y(s)
        if value is None:
            continue
        if s.t - last > GAP_S or not runs:
            runs.append([])
        runs[-1].append(f"{x(s.t):.1f},{value:.1f}")
        last = s.t
    return [f'<polyline class="{css}" fill="none" stroke="{color}" stroke-width="1.2" '
            f'points="{" ".join(r)}"/>' for r in runs]


def _motions(segs: Sequence[Segment], sc: Scales, op_colors: dict[str, str]) -> list[str]:
    """The ACT-nodes as bars: top level coloured by operation, sub-motions below."""
    top = min((s.level for s in segs), default=1)
    sub_colors = colors(s.motion for s in segs if s.level > top)
    out = []
    for s in segs:
        x0, x1 = sc.x(s.t_start), sc.x(s.t_end)
        y, h = (MOTIONS_Y, 18) if s.level == top else (MOTIONS_Y + 21, 14)
        label = (s.operation or "?") if s.level == top else s.motion
        fill = op_colors.get(label, "#888") if s.level == top else sub_colors[s.motion]
        info = (f"{s.name}: {s.motion} = {s.operation or '?'}, {s.t_start:.2f}-{s.t_end:.2f} s,"
                f" begun by :{s.initial_event or '-'}, ended by :{s.final_event or '-'}")
        out.append(f'<g class="motion level-{s.level}"><title>{esc(info)}</title>'
                   f'<rect x="{x0:.1f}" y="{y}" width="{max(1.0, x1 - x0):.1f}" height="{h}" '
                   f'fill="{fill}" stroke="white"/>')
        if text_fits(label, x1 - x0):
            out.append(f'<text x="{x0 + 2:.1f}" y="{y + h - 4}" fill="white">{esc(label)}</text>')
        out.append("</g>")
    return out


def cuts(segs: Sequence[Segment]) -> list[tuple[float, int, list[str], str]]:
    """Segmentation points: (t, top level involved, events that cut, a sentence why)."""
    at: dict[float, list[tuple[str, Segment]]] = {}
    for s in segs:
        at.setdefault(round(s.t_start, 3), []).append(("begins", s))
        at.setdefault(round(s.t_end, 3), []).append(("ends", s))
    out = []
    for t in sorted(at):
        events = [s.final_event if how == "ends" else s.initial_event for how, s in at[t]]
        names = list(dict.fromkeys(e for e in events if e))
        why = "; ".join(f"{s.name} ({s.operation or '?'}) {how}"
                        f"{' on :' + e if e else ''}" for (how, s), e in zip(at[t], events,
                                                                           strict=True))
        out.append((t, min(s.level for _, s in at[t]), names, f"t = {t:.2f} s: {why}"))
    return out


def _cuts(segs: Sequence[Segment], sc: Scales, bottom: float) -> list[str]:
    """Vertical lines at every cut, labelled with its events (rotated)."""
    top = min((s.level for s in segs), default=1)
    out = []
    for t, level, names, why in cuts(segs):
        x = sc.x(t)
        dash = "" if level == top else ' stroke-dasharray="3,3"'
        label = " ".join(f":{n}" for n in names)
        out.append(f'<g class="cut" data-t="{t:.3f}" data-events="{esc(" ".join(names))}">'
                   f"<title>{esc(why)}</title>"
                   f'<line x1="{x:.1f}" y1="{CUTS_Y}" x2="{x:.1f}" y2="{bottom}" '
                   f'stroke="{CUT_COLOR}" stroke-width="{1.2 if level == top else 0.8}"'
                   f' opacity="0.7"{dash}/>'
                   f'<text transform="translate({x - 2:.1f},{CUTS_Y + CUTS_H - 2}) rotate(-90)"'
                   f' font-size="9">{esc(label)}</text></g>')
    return out


def speed_thresholds(features: MotionFeatures) -> list[tuple[float, str, str]]:
    """(speed, 'V_H1 = V_L2', why) per distinct threshold, from the rules' ranges."""
    by_value: dict[float, list[tuple[str, str]]] = {}
    for k, (event, (low, high)) in enumerate(features.ranges.items(), 1):
        by_value.setdefault(float(low), []).append((f"V_L{k}", event))
        by_value.setdefault(float(high), []).append((f"V_H{k}", event))
    return [(v, " = ".join(n for n, _ in names),
             "; ".join(f"{n}: threshold of :{e}" for n, e in names))
            for v, names in sorted(by_value.items())]


def _panels(trace: MotionTrace, features: MotionFeatures, sc: Scales) -> list[str]:
    """Speed, angle and height panels with their thresholds and curves."""
    x1 = sc.x(sc.t_max)
    out = [f'<rect x="{LEFT}" y="{y}" width="{x1 - LEFT:.1f}" height="{h}" fill="none" '
           f'stroke="#bbb"/>' for y, h in ((SPEED_Y, SPEED_H), (ANGLE_Y, ANGLE_H), (Z_Y, Z_H))]
    for text, y in (("speed mm/s", SPEED_Y), ("(log scale)", SPEED_Y + 12),
                    ("angle from", ANGLE_Y), ("straight down", ANGLE_Y + 12),
                    ("hand height", Z_Y), ("z mm", Z_Y + 12)):
        out.append(f'<text x="4" y="{y + 10}" font-size="11">{text}</text>')
    for d in range(sc.decades + 1):
        y = sc.speed(10.0 ** d)
        out.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{x1:.1f}" y2="{y:.1f}" stroke="#eee"/>'
                   f'<text x="{LEFT - 4}" y="{y + 3:.1f}" text-anchor="end">{10 ** d}</text>')
    for v, name, why in speed_thresholds(features):
        y = sc.speed(v)
        out.append(f'<g class="threshold speed" data-value="{v:g}" data-name="{esc(name)}">'
                   f"<title>{esc(why)} = {v:g} mm/s</title>"
                   f'<line x1="{LEFT}" y1="{y:.1f}" x2="{x1:.1f}" y2="{y:.1f}" '
                   f'stroke="{THRESHOLD_COLOR}" stroke-dasharray="6,3"/>'
                   f'<text x="{x1 + 4:.1f}" y="{y + 3:.1f}" fill="{THRESHOLD_COLOR}">'
                   f"{esc(name)} = {v:g}</text></g>")
    for a, name in ((features.angle_down, "A_D"), (features.angle_up, "A_U")):
        y = sc.angle(a)
        out.append(f'<g class="threshold angle" data-value="{a:g}" data-name="{name}">'
                   f"<title>{name} = {a:g} degrees from straight down (footnote 11)</title>"
                   f'<line x1="{LEFT}" y1="{y:.1f}" x2="{x1:.1f}" y2="{y:.1f}" '
                   f'stroke="{THRESHOLD_COLOR}" stroke-dasharray="6,3"/>'
                   f'<text x="{x1 + 4:.1f}" y="{y + 3:.1f}" fill="{THRESHOLD_COLOR}">'
                   f"{name} = {a:g}°</text></g>")
    for a in (0, 90, 180):
        out.append(f'<text x="{LEFT - 4}" y="{sc.angle(a) + 3:.1f}" text-anchor="end">{a}</text>')
    out.append(f'<text x="{LEFT - 4}" y="{Z_Y + 8}" text-anchor="end">{sc.z_max:.0f}</text>')
    out += _polylines(trace, lambda s: sc.speed(s.speed), sc.x, "speed", "#1f5fa0")
    out += _polylines(trace, lambda s: None if s.angle is None else sc.angle(s.angle), sc.x,
                      "angle", "#2e7d32")
    out += _polylines(trace, lambda s: sc.z(s.z), sc.x, "height", "#6a3d9a")
    return out


def feature_runs(events: Sequence[LoggedEvent], event: str, period: float
                 ) -> list[tuple[float, float, str, str]]:
    """Runs of one feature event's value: (t0, t1, value, motion asking)."""
    runs: list[list[Any]] = []
    for e in events:
        if e.event != event or e.value is None:
            continue
        if runs and runs[-1][2] == e.value and e.t - runs[-1][1] <= GAP_S:
            runs[-1][1] = e.t
        else:
            runs.append([e.t, e.t, e.value, e.motion])
    return [(t0, t1 + period, v, m) for t0, t1, v, m in runs]


def _lanes(trace: MotionTrace, features: MotionFeatures, sc: Scales, y0: float,
           period: float) -> tuple[list[str], float]:
    """One lane per speed range (Table IV values) and one of the other events."""
    value_colors = colors(features.values(), ordered=True)
    out, y = [], y0
    for event in features.ranges:
        out.append(f'<text x="4" y="{y + 11}" font-size="11">:{esc(event)}</text>')
        for t0, t1, value, motion in feature_runs(trace.events, event, period):
            info = f":{event} = {value} (asked by {motion}), {t0:.2f}-{t1:.2f} s"
            out.append(f'<rect class="feature" data-event="{esc(event)}" '
                       f'data-value="{esc(value)}" x="{sc.x(t0):.1f}" y="{y}" '
                       f'width="{max(1.0, (t1 - t0) * PX_PER_S):.1f}" height="{LANE_H}" '
                       f'fill="{value_colors.get(value, "#888")}"><title>{esc(info)}</title>'
                       "</rect>")
        y += LANE_H + 3
    point = [e for e in trace.events if e.event not in features.ranges or e.value is None]
    event_colors = colors(e.event for e in point)
    out.append(f'<text x="4" y="{y + 11}" font-size="11">other events</text>')
    for e in point:
        info = f"t = {e.t:.2f} s: :{e.event}{' = ' + e.value if e.value else ''} ({e.motion})"
        x = sc.x(e.t)
        out.append(f'<line class="event" data-event="{esc(e.event)}" x1="{x:.1f}" y1="{y}" '
                   f'x2="{x:.1f}" y2="{y + LANE_H}" stroke="{event_colors[e.event]}" '
                   f'stroke-width="3"><title>{esc(info)}</title></line>')
    return out, y + LANE_H + 3


def motion_plot_svg(trace: MotionTrace, features: MotionFeatures,
                    op_colors: dict[str, str] | None = None) -> str:
    """The whole plot as one ``<svg id="motion-plot">`` (scaled by its viewBox)."""
    sc = Scales(trace, features)
    period = _frame_period(trace)
    lanes, bottom = _lanes(trace, features, sc, Z_Y + Z_H + 8, period)
    height = bottom + 22
    body = _motions(trace.segments, sc, op_colors or {}) + _panels(trace, features, sc) + lanes
    body += _cuts(trace.segments, sc, bottom)
    for s in range(0, int(sc.t_max) + 1, TICK_S):
        x = sc.x(s)
        body.append(f'<line x1="{x}" y1="{bottom}" x2="{x}" y2="{bottom + 5}" stroke="#555"/>'
                    f'<text x="{x + 2}" y="{bottom + 16}">{s}s</text>')
    return (f'<svg id="motion-plot" xmlns="http://www.w3.org/2000/svg" width="{sc.width:.0f}" '
            f'height="{height:.0f}" viewBox="0 0 {sc.width:.0f} {height:.0f}" '
            'font-family="monospace" font-size="10">\n' + "\n".join(body) + "\n</svg>")


def motion_legend(trace: MotionTrace, features: MotionFeatures) -> str:
    """The plot's colour keys: Table IV values, the other events, and the lines."""
    values = colors(features.values(), ordered=True)
    point = [e.event for e in trace.events if e.event not in features.ranges or e.value is None]
    events = colors(point)
    lines = [("speed", "#1f5fa0"), ("angle from straight down", "#2e7d32"),
             ("hand height", "#6a3d9a"), ("thresholds (rules/motion-features.yaml)",
                                          THRESHOLD_COLOR), ("cut (segmentation point)", CUT_COLOR)]
    return (legend(list(values.items()), "motion-values", "Table IV values:")
            + legend(list(events.items()), "motion-events", "events:")
            + legend(lines, "motion-lines", "lines:"))


def _frame_period(trace: MotionTrace) -> float:
    """The smallest gap between samples (one frame), 1/30 s without samples."""
    gaps = [b.t - a.t for a, b in zip(trace.samples, trace.samples[1:], strict=False)
            if b.t > a.t]
    return min(gaps, default=1 / 30)
