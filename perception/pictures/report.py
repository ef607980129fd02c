"""report.html: one self-contained page showing what was watched, learned and done.

Everything is inline (CSS and JS from ``assets/``, SVG, images and the H.264
videos as data URIs): the file can be mailed or opened offline from any folder.

| section (id)   | what                                                                 |
|----------------|----------------------------------------------------------------------|
| `scenario`     | the scenario file                                                    |
| `video`        | the demonstration as seen on the monitor (Fig. 19): video, frame strip |
| `sequence`     | timeline of recognized against demonstrated operations, with legend   |
| `motion`       | the hand's motion features and the cuts (perception.pictures.motionplot) |
| `plan`         | the plan picture (Fig. 13 / 22), zoomable, and its plot text          |
| `execution`    | the robot's work: video, frame strip, initial and final state pictures |
| `commands`     | the manipulator commands (Table IX)                                  |
| `verification` | execution.json as tables (perception.pictures.tables)                |

A frame strip's label is the time drawn in the frame it shows (the
demonstration's clock, or the robot's); the two strips never share an axis.
"""

from __future__ import annotations

import base64
import re
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from perception.pictures.exectimeline import execution_timeline_svg
from perception.pictures.svgkit import esc
from perception.pictures.tables import execution_tables
from perception.pictures.timeline import timeline_legend, timeline_svg

Frames = Sequence[tuple[float, np.ndarray]]
FIT_LIMIT = 1.5  # at zoom 1 a picture is drawn at most this many times its own size


def _asset(name: str) -> str:
    """The text of ``assets/NAME`` (the page's CSS and JS)."""
    return resources.files("perception.pictures").joinpath("assets", name).read_text()


def jpeg_uri(img: np.ndarray, quality: int = 70) -> str:
    """An image as a data URI (JPEG)."""
    ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, quality])
    if not ok:  # pragma: no cover
        raise RuntimeError("JPEG encoding failed")
    return "data:image/jpeg;base64," + base64.b64encode(buf.tobytes()).decode("ascii")


def frame_label(t: float) -> str:
    """A frame's time as the monitor panel writes it (overlay.draw_monitor: 2 decimals)."""
    return f"t = {t:.2f} s"


def video_html(ident: str, mp4: bytes | None, frames: Frames = ()) -> str:
    """A <video> playing ``mp4`` from a data URI (H.264, video.VideoFile); '' without one.

    The first of ``frames`` is its poster: shown before it plays, and in printouts.
    """
    if not mp4:
        return ""
    uri = "data:video/mp4;base64," + base64.b64encode(mp4).decode("ascii")
    poster = f' poster="{jpeg_uri(frames[0][1])}"' if frames else ""
    return f'<video id="{ident}" controls preload="metadata"{poster} src="{uri}"></video>'


def strip_html(ident: str, frames: Frames) -> str:
    """A frame strip: one frame shown at a time, picked with a slider, labelled with its time."""
    if not frames:
        return f'<p id="{ident}">no frames were kept</p>'
    parts = [f'<div class="strip" id="{ident}"><div><img class="view" alt="frame" '
             f'width="{frames[0][1].shape[1]}"></div><input class="slider" type="range" min="0" '
             f'max="{len(frames) - 1}" value="0" aria-label="frame"><span class="time"></span>'
             '<div class="frames" hidden>']
    parts += [f'<img class="frame" data-t="{t:.3f}" data-label="{frame_label(t)}" '
              f'src="{jpeg_uri(img)}" alt="{frame_label(t)}">' for t, img in frames]
    parts.append("</div></div>")
    return "".join(parts)


def zoomable(ident: str, svg: str) -> str:
    """A picture that fits its box's width at zoom 1, with -, fit and + buttons."""
    match = re.search(r'<svg[^>]*\swidth="([\d.]+)"', svg)
    if match:  # at zoom 1, never blown up beyond FIT_LIMIT x its own size
        cap = float(match.group(1)) * FIT_LIMIT
        svg = svg.replace("<svg ", f'<svg style="max-width:calc(var(--zoom) * {cap:.0f}px)" ', 1)
    return (f'<div class="zoom" data-for="{ident}"><button data-step="0.8" title="zoom out">'
            '-</button><button data-step="fit" title="fit the width">fit</button>'
            '<button data-step="1.25" title="zoom in">+</button><span class="level">100%</span>'
            f'</div><div class="scroll zoomable" id="{ident}">{svg}</div>')


def _sequence(truth: list[dict[str, Any]], ops: list[dict[str, Any]]) -> str:
    """Timeline section: a verdict line, the timeline, its legend and the sequence text."""
    got = [o.get("operation") for o in ops]
    same = got == [t["operation"] for t in truth]
    return ('<section id="sequence"><h2>Recognized sequence vs. ground truth</h2>'
            f'<p class="{"ok" if same else "bad"}">{len(got)} operations recognized, '
            f'{len(truth)} demonstrated: {"identical" if same else "they differ"}</p>'
            + zoomable("timeline-view", timeline_svg(truth, ops)) + timeline_legend(truth, ops)
            + '<div id="op-info"></div>'
            f"<pre>{esc(' '.join(str(g) for g in got))}</pre></section>")


def _motion(motion_svg: str, motion_legend: str) -> str:
    """Motion-feature section (perception.pictures.motionplot), if it was recorded."""
    if not motion_svg:
        return '<section id="motion"><h2>Motion features</h2><p>not recorded</p></section>'
    return ('<section id="motion"><h2>Motion features and segmentation (Table IV, Table VII)'
            '</h2><p class="note">The hand\'s speed and its angle from straight down, as the '
            "hand-tracker measured them, against the thresholds of rules/motion-features.yaml "
            "(V_L, V_H per speed range; A_D, A_U). Vertical lines are the points where the "
            "recognizer cut the motion, labelled with the events that cut it (solid: between "
            "top-level motions; dashed: between sub-motions). Hover over a mark for details."
            f"</p>{zoomable('motion-view', motion_svg)}{motion_legend}</section>")


def _execution(frames: Frames, mp4: bytes | None,
               states: Sequence[tuple[str, str, np.ndarray]], ran: bool,
               monitor: Mapping[str, Any] | None = None) -> str:
    """The robot's work: video, frame strip (robot time), the monitor's timeline and
    state pictures."""
    if not ran:
        return '<section id="execution"><h2>Execution</h2><p>no execution</p></section>'
    timeline = execution_timeline_svg(monitor) if isinstance(monitor, Mapping) else ""
    figures = "".join(f'<figure id="{esc(key)}"><img src="{jpeg_uri(img, 85)}" alt="{esc(key)}">'
                      f"<figcaption>{esc(caption)}</figcaption></figure>"
                      for key, caption, img in states)
    return ('<section id="execution"><h2>Execution</h2>'
            + video_html("execution-video", mp4, frames) + strip_html("execution-frames", frames)
            + (f"<h3>Timeline: ACHIEVEs, detections, repairs</h3>{timeline}" if timeline else "")
            + f'<h3>Initial and final state</h3><div id="states">{figures or "<p>none</p>"}'
            "</div></section>")


def _verification(execution: Mapping[str, Any] | None) -> str:
    """The verdict line and execution.json's tables."""
    if execution is None:
        return '<section id="verification"><h2>Verification</h2><p>no execution</p></section>'
    ok = bool(execution.get("success"))
    return (f'<section id="verification"><h2>Verification</h2><p class="{"ok" if ok else "bad"}">'
            f'{"verified: the executed structure matches the plan" if ok else "NOT verified"}'
            f"</p>{execution_tables(execution)}</section>")


def render_report(*, title: str, scenario_text: str, actions: dict[str, Any],
                  truth: list[dict[str, Any]], plan: dict[str, Any] | None,
                  plan_text: str | None, commands_text: str | None,
                  execution: Mapping[str, Any] | None, frames: Frames = (),
                  video_mp4: bytes | None = None, execution_frames: Frames = (),
                  execution_mp4: bytes | None = None,
                  states: Sequence[tuple[str, str, np.ndarray]] = (),
                  motion_svg: str = "", motion_legend: str = "") -> str:
    """The whole report as one HTML string (see the module docstring for the parts)."""
    from perception.pictures.plandraw import svg_text

    ops = actions.get("operations", [])
    plan_svg = zoomable("plan-view", svg_text(plan)) if plan else "<p>no plan was learned</p>"
    body = [
        f"<h1>{esc(title)}</h1>",
        f'<section id="scenario"><h2>Scenario</h2><pre>{esc(scenario_text)}</pre></section>',
        '<section id="video"><h2>Demonstration</h2>'
        + video_html("demonstration-video", video_mp4, frames)
        + strip_html("demonstration-frames", frames) + "</section>",
        _sequence(truth, ops),
        _motion(motion_svg, motion_legend),
        f'<section id="plan"><h2>Plan (Fig. 13 / Fig. 22)</h2>{plan_svg}'
        f'<h3>Plot text</h3><pre id="plan-text">{esc(plan_text or "")}</pre></section>',
        _execution(execution_frames, execution_mp4, states, execution is not None,
                   execution.get("monitor") if execution is not None else None),
        f'<section id="commands"><h2>Commands</h2><pre>{esc(commands_text or "none")}</pre>'
        "</section>",
        _verification(execution),
    ]
    return ('<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{esc(title)}</title><style>{_asset('report.css')}</style></head><body>\n"
            + "\n".join(body) + f"\n<script>{_asset('report.js')}</script></body></html>\n")


def pick_frames(frames: Frames, n: int = 60) -> list[tuple[float, np.ndarray]]:
    """At most ``n`` frames evenly spread over a recording (a frame strip)."""
    if len(frames) <= n:
        return list(frames)
    idx = np.linspace(0, len(frames) - 1, n).round().astype(int)
    return [frames[i] for i in idx]


def truth_of(scenario: Any, rules: Any) -> list[dict[str, Any]]:
    """The ground-truth operations of a scenario's demonstration, for the timeline."""
    from perception.world.groundtruth import ground_truth

    return [{"operation": t.operation, "t_start": t.t_start, "t_end": t.t_end}
            for t in ground_truth(scenario, rules)]


def object_sizes(scenario: Any, actions: Mapping[str, Any]) -> dict[str, tuple[float, ...]]:
    """Box size per plan object name: its recognized shape (actions.json), else its taught one."""
    sizes = {n: tuple(scenario.shapes[o.shape]) for n, o in scenario.teach.objects.items()}
    for name, obj in (actions.get("objects") or {}).items():
        if obj.get("shape") in scenario.shapes:
            sizes[name] = tuple(scenario.shapes[obj["shape"]])
    return sizes


def _read(path: str | Path | None) -> bytes | None:
    """A video file's bytes, or None when there is none."""
    return Path(path).read_bytes() if path is not None and Path(path).is_file() else None


def run_report(scenario: Any, rules: Any, actions: dict[str, Any], plan: dict[str, Any] | None,
               plan_text: str | None, execution: Any = None, frames: Frames = (),
               execution_frames: Frames = (), videos: Mapping[str, str | Path] | None = None,
               trace: Any = None, execution_json: Mapping[str, Any] | None = None,
               max_frames: int = 40) -> str:
    """report.html for one ``lbw run``: ``execution`` is an ExecutionResult or None.

    ``frames`` / ``execution_frames`` are (t, image) pairs as overlay's recorders keep
    them (at most ``max_frames`` of each are embedded); ``videos`` maps
    ``demonstration`` / ``execution`` to MP4 files; ``trace`` is a
    ``motiontrace.MotionTrace`` of the watch; ``execution_json`` is execution.json as
    published (default: the execution's own report).
    """
    from perception.pictures.motionplot import motion_legend, motion_plot_svg
    from perception.pictures.statepics import state_pictures
    from perception.pictures.timeline import operation_colors

    text = Path(scenario.file).read_text() if Path(scenario.file).is_file() else \
        f"# {scenario.name} (no file)"
    truth = truth_of(scenario, rules)
    videos = videos or {}
    motion = ("", "")
    if trace is not None:
        palette = operation_colors(truth, actions.get("operations", []))
        motion = (motion_plot_svg(trace, rules.motion_features, palette),
                  motion_legend(trace, rules.motion_features))
    states = state_pictures(execution.views, execution.report, object_sizes(scenario, actions)) \
        if execution is not None else []
    return render_report(
        title=f"lbw run: {scenario.name}", scenario_text=text, actions=actions, truth=truth,
        plan=plan, plan_text=plan_text,
        commands_text=execution.commands_text if execution is not None else None,
        execution=(execution_json or execution.report) if execution is not None else None,
        frames=pick_frames(frames, max_frames), video_mp4=_read(videos.get("demonstration")),
        execution_frames=pick_frames(execution_frames, max_frames),
        execution_mp4=_read(videos.get("execution")), states=states,
        motion_svg=motion[0], motion_legend=motion[1])
