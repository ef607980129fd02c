"""report.html: one self-contained page showing what was watched, learned and done.

Sections: the scenario, the demonstration (an MP4 as a base64 data URI when
given, and always a strip of frames with a slider), the recognized sequence as
a timeline against the ground truth, the plan picture (perception.pictures.plandraw)
with its plot text, the manipulator commands and the verification result.
Everything is inline (CSS, JS, SVG, images as data URIs): the file can be
mailed or opened offline. Element ids the tests and readers rely on:
``scenario``, ``video``, ``frames``, ``timeline``, ``plan``, ``plan-text``,
``commands``, ``verification``.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from lbw_engine.rules import RuleSet
from perception.pictures.plandraw import svg_text

ROW_H, LABEL_W, PX_PER_S = 26, 110, 8.0
PALETTE = ("#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1",
           "#ff9da7", "#9c755f", "#bab0ac")

_CSS = """
body{font-family:system-ui,sans-serif;margin:24px;color:#222;max-width:1400px}
h1{font-size:22px} h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}
pre{background:#f6f6f6;padding:8px;overflow:auto;max-height:420px;font-size:12px}
.ok{color:#17702a;font-weight:bold} .bad{color:#b3261e;font-weight:bold}
.scroll{overflow-x:auto;border:1px solid #eee}
#frame-view{image-rendering:pixelated;border:1px solid #ccc}
#op-info{font-family:monospace;min-height:1.2em}
table.kv td{padding:2px 10px 2px 0;vertical-align:top}
"""

_JS = """
(function(){
  var frames = document.querySelectorAll('#frames img.frame');
  var view = document.getElementById('frame-view');
  var slider = document.getElementById('frame-slider');
  var label = document.getElementById('frame-time');
  function show(i){
    if(!frames.length){return;}
    view.src = frames[i].src;
    label.textContent = frames[i].getAttribute('data-t') + ' s';
  }
  if(slider){ slider.addEventListener('input', function(){ show(+slider.value); }); show(0); }
  var info = document.getElementById('op-info');
  document.querySelectorAll('#timeline .op').forEach(function(r){
    r.addEventListener('mouseenter', function(){ info.textContent = r.getAttribute('data-info'); });
  });
  document.body.setAttribute('data-ready', 'yes');
})();
"""


def _esc(text: Any) -> str:
    """HTML-escaped text."""
    return html.escape(str(text), quote=True)


def _colors(names: Sequence[str]) -> dict[str, str]:
    """A stable colour per operation name (sorted names take palette entries in turn)."""
    return {n: PALETTE[i % len(PALETTE)] for i, n in enumerate(sorted(set(names)))}


def timeline_svg(truth: list[dict[str, Any]], ops: list[dict[str, Any]]) -> str:
    """Two rows of time bars: the ground truth and the recognized operations."""
    rows = [("ground truth", "truth", truth), ("recognized", "recognized", ops)]
    ends = [float(o["t_end"]) for _, _, r in rows for o in r if o.get("t_end") is not None]
    t_max = max(ends, default=1.0)
    width = LABEL_W + int(t_max * PX_PER_S) + 20
    colors = _colors([o["operation"] or "?" for _, _, r in rows for o in r])
    out = [f'<svg id="timeline" xmlns="http://www.w3.org/2000/svg" width="{width}" '
           f'height="{ROW_H * 2 + 30}" font-family="monospace" font-size="10">']
    for k, (label, css, items) in enumerate(rows):
        y = 4 + k * (ROW_H + 4)
        out.append(f'<text x="4" y="{y + 17}" font-size="12">{label}</text>')
        for i, o in enumerate(items):
            t0 = float(o.get("t_start") or 0.0)
            t1 = float(o["t_end"]) if o.get("t_end") is not None else t_max
            x, w = LABEL_W + t0 * PX_PER_S, max(1.0, (t1 - t0) * PX_PER_S)
            name = o["operation"] or "?"
            info = f"{label} #{i}: {name} {t0:.2f}-{t1:.2f} s"
            out.append(f'<g class="op {css}" data-info="{_esc(info)}"><title>{_esc(info)}</title>'
                       f'<rect x="{x:.1f}" y="{y}" width="{w:.1f}" height="{ROW_H}" '
                       f'fill="{colors[name]}" stroke="white"/>')
            if w > 7 * len(name):
                out.append(f'<text x="{x + 2:.1f}" y="{y + 16}" fill="white">{_esc(name)}</text>')
            out.append("</g>")
    for s in range(0, int(t_max) + 1, 10):  # a tick every 10 s
        x = LABEL_W + s * PX_PER_S
        out.append(f'<line x1="{x}" y1="{2 * ROW_H + 10}" x2="{x}" y2="{2 * ROW_H + 15}" '
                   f'stroke="#555"/><text x="{x + 2}" y="{2 * ROW_H + 26}">{s}s</text>')
    out.append("</svg>")
    return "\n".join(out)


def _jpeg_uri(img: np.ndarray, quality: int = 80) -> str:
    """An image as a data URI (JPEG)."""
    ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:  # pragma: no cover
        raise RuntimeError("JPEG encoding failed")
    return "data:image/jpeg;base64," + base64.b64encode(buf.tobytes()).decode("ascii")


def _video_section(frames: Sequence[tuple[float, np.ndarray]], mp4: bytes | None) -> str:
    """The MP4 (if any) and the frame strip with a slider."""
    parts = ['<section id="video"><h2>Demonstration</h2>']
    if mp4:
        uri = "data:video/mp4;base64," + base64.b64encode(mp4).decode("ascii")
        parts.append(f'<video controls width="768" src="{uri}"></video>')
    if frames:
        parts.append(f'<div><img id="frame-view" alt="frame" width="{frames[0][1].shape[1]}">'
                     f'</div><input id="frame-slider" type="range" min="0" '
                     f'max="{len(frames) - 1}" value="0" style="width:600px"> '
                     '<span id="frame-time"></span>')
        parts.append('<div id="frames" style="display:none">')
        parts += [f'<img class="frame" data-t="{t:.1f}" src="{_jpeg_uri(img)}" alt="t={t:.1f}">'
                  for t, img in frames]
        parts.append("</div>")
    parts.append("</section>")
    return "\n".join(parts)


def _verification(execution: dict[str, Any] | None) -> str:
    """The verdict and the mismatches, if any."""
    if execution is None:
        return '<section id="verification"><h2>Verification</h2><p>no execution</p></section>'
    ok = bool(execution.get("success"))
    rows = "".join(f"<tr><td>{_esc(k)}</td><td>{_esc(v)}</td></tr>"
                   for k, v in execution.items() if k in ("stage", "commands", "failure", "robot"))
    mism = "".join(f"<li>{_esc(m.get('message', m))}</li>"
                   for m in execution.get("mismatches", []) or [])
    return (f'<section id="verification"><h2>Verification</h2><p class="{"ok" if ok else "bad"}">'
            f'{"verified: the executed structure matches the plan" if ok else "NOT verified"}'
            f'</p><table class="kv">{rows}</table>{"<ul>" + mism + "</ul>" if mism else ""}'
            "</section>")


def render_report(*, title: str, scenario_text: str, actions: dict[str, Any],
                  truth: list[dict[str, Any]], plan: dict[str, Any] | None,
                  plan_text: str | None, commands_text: str | None,
                  execution: dict[str, Any] | None,
                  frames: Sequence[tuple[float, np.ndarray]] = (),
                  video_mp4: bytes | None = None) -> str:
    """The whole report as one HTML string (see the module docstring for the parts)."""
    ops = actions.get("operations", [])
    got = [o["operation"] for o in ops]
    expected = [t["operation"] for t in truth]
    same = got == expected
    plan_svg = svg_text(plan) if plan else "<p>no plan was learned</p>"
    body = [
        f"<h1>{_esc(title)}</h1>",
        f'<section id="scenario"><h2>Scenario</h2><pre>{_esc(scenario_text)}</pre></section>',
        _video_section(frames, video_mp4),
        '<section id="sequence"><h2>Recognized sequence vs. ground truth</h2>'
        f'<p class="{"ok" if same else "bad"}">{len(got)} operations recognized, '
        f'{len(expected)} demonstrated: {"identical" if same else "they differ"}</p>'
        f'<div class="scroll">{timeline_svg(truth, ops)}</div><div id="op-info"></div>'
        f"<pre>{_esc(' '.join(got))}</pre></section>",
        f'<section id="plan"><h2>Plan (Fig. 13 / Fig. 22)</h2><div class="scroll">{plan_svg}'
        f'</div><h3>Plot text</h3><pre id="plan-text">{_esc(plan_text or "")}</pre></section>',
        f'<section id="commands"><h2>Commands</h2><pre>{_esc(commands_text or "none")}</pre>'
        "</section>",
        _verification(execution),
    ]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{_esc(title)}</title><style>{_CSS}</style></head><body>\n"
            + "\n".join(body) + f"\n<script>{_JS}</script></body></html>\n")


def pick_frames(frames: Sequence[tuple[float, np.ndarray]], n: int = 60
                ) -> list[tuple[float, np.ndarray]]:
    """At most ``n`` frames evenly spread over a recording (the report's frame strip)."""
    if len(frames) <= n:
        return list(frames)
    idx = np.linspace(0, len(frames) - 1, n).round().astype(int)
    return [frames[i] for i in idx]


def truth_of(scenario: Any, rules: RuleSet) -> list[dict[str, Any]]:
    """The ground-truth operations of a scenario's demonstration, for the timeline."""
    from perception.world.groundtruth import ground_truth

    return [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
            for t in ground_truth(scenario, rules)]


def run_report(scenario: Any, rules: RuleSet, actions: dict[str, Any],
               plan: dict[str, Any] | None,
               plan_text: str | None, execution: Any = None,
               frames: Sequence[tuple[float, np.ndarray]] = (),
               video_mp4: bytes | None = None, max_frames: int = 60) -> str:
    """report.html for one ``lbw run``: ``execution`` is an ExecutionResult or None.

    ``frames`` are (t, image) pairs, e.g. the ones ``perception.pictures.overlay``'s
    ``record_demonstration`` keeps; at most ``max_frames`` are embedded.
    """
    text = Path(scenario.file).read_text() if Path(scenario.file).is_file() else \
        f"# {scenario.name} (no file)"
    return render_report(
        title=f"lbw run: {scenario.name}", scenario_text=text, actions=actions,
        truth=truth_of(scenario, rules), plan=plan, plan_text=plan_text,
        commands_text=execution.commands_text if execution is not None else None,
        execution=execution.report if execution is not None else None,
        frames=pick_frames(frames, max_frames), video_mp4=video_mp4)
