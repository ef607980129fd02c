"""Plan pictures: a plan.json drawn as a tree in the spirit of Fig. 13 and Fig. 22.

Each operator is a box showing its class, name, base and target (and special
when it has one); the recognized operations under FETCH/PUT are small leaf
boxes. A ``$sequence`` plot joins consecutive children with arrows; a
``$parallel`` plot draws an arc across the lines from the parent to its
children (the AND arc of Fig. 13). The layout is computed once as a list of
drawing primitives, then written either as SVG text or as an OpenCV image, so
the two always agree (the same split pymunk makes between physics and its
debug-draw adapter).

    pic = plan_picture(plan)        # plan: the plan.json dict
    svg = to_svg(pic)               # str, valid XML; <g id="op-NAME" class="operator">
    img = to_image(pic)             # BGR uint8 array (cv2.imwrite for a PNG)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any
from xml.sax.saxutils import escape, quoteattr

import cv2
import numpy as np

CHAR_W = 7.2  # px per character of the 12 px monospace font (SVG) / Hershey scale 0.4
LINE_H = 15  # px between text lines inside a box
PAD = 6  # px inside a box
H_GAP = 18  # px between sibling subtrees
V_GAP = 46  # px between levels
MARGIN = 16
ARC_R = 22  # px: radius of the $parallel arc around the parent's bottom centre

# Box fill per operator class (BGR-free hex, used for both outputs).
CLASS_FILL = {
    "BUILD": "#cfe3ff", "PACHIEVE": "#ffe2b8", "ACHIEVE": "#d9f2d0",
    "FETCH": "#f4f4f4", "PUT": "#f4f4f4", "FAKE": "#f6d6d6",
}
LEAF_FILL = "#ffffff"


@dataclass
class Rect:
    """A box; ``ident`` becomes the SVG group id."""

    x: float
    y: float
    w: float
    h: float
    fill: str
    ident: str
    css: str
    lines: list[tuple[str, bool]]  # (text, bold)


@dataclass
class Path:
    """A polyline, optionally ending in an arrow head."""

    points: list[tuple[float, float]]
    arrow: bool = False
    css: str = "edge"


@dataclass
class Picture:
    """Drawing primitives of a plan tree, in pixels."""

    width: float
    height: float
    rects: list[Rect] = field(default_factory=list)
    paths: list[Path] = field(default_factory=list)


@dataclass
class _Node:
    """One box of the tree and its children, grouped as in the plot."""

    name: str
    lines: list[tuple[str, bool]]
    fill: str
    css: str
    plot: Any = None
    children: list[_Node] = field(default_factory=list)
    w: float = 0.0
    h: float = 0.0
    x: float = 0.0  # left edge
    y: float = 0.0
    span: float = 0.0  # width of the whole subtree


def _names(plot: Any) -> list[str]:
    """The $action names of a plot, left to right."""
    if not isinstance(plot, list) or not plot:
        return []
    if plot[0] == "$action":
        return [plot[1]]
    return [n for sub in plot[1:] for n in _names(sub)]


def _fmt(label: str, names: list[str]) -> str:
    """``label: a b c`` (``-`` for an empty list)."""
    return f"{label}: {' '.join(names) if names else '-'}"


def _build(plan: dict, name: str, seen: set[str]) -> _Node:
    """The subtree under ``name`` (operators recursively, operations as leaves)."""
    ops = plan["operators"]
    if name not in ops or name in seen:
        return _Node(name, [(name, False)], LEAF_FILL, "leaf")
    seen.add(name)
    op = ops[name]
    lines = [(f"{op['class']} {name}", True), (_fmt("base", op.get("base", [])), False),
             (_fmt("target", op.get("target", [])), False)]
    if op.get("special"):
        lines.append((_fmt("special", op["special"]), False))
    node = _Node(name, lines, CLASS_FILL.get(op["class"], "#eeeeee"), "operator", op.get("plot"))
    node.children = [_build(plan, child, seen) for child in _names(op.get("plot"))]
    return node


def _measure(node: _Node) -> None:
    """Box sizes and subtree spans, bottom up."""
    node.w = max(len(t) for t, _ in node.lines) * CHAR_W + 2 * PAD
    node.h = len(node.lines) * LINE_H + 2 * PAD - 3
    for child in node.children:
        _measure(child)
    kids = sum(c.span for c in node.children) + H_GAP * max(0, len(node.children) - 1)
    node.span = max(node.w, kids)


def _place(node: _Node, left: float, top: float) -> None:
    """Centre each box over its children's span, children one gap below it."""
    node.y = top
    node.x = left + (node.span - node.w) / 2
    if node.children:
        kids = sum(c.span for c in node.children) + H_GAP * (len(node.children) - 1)
        x = left + (node.span - kids) / 2
        below = top + node.h + V_GAP
        for child in node.children:
            _place(child, x, below)
            x += child.span + H_GAP


def _walk(node: _Node):
    """All nodes, pre-order."""
    yield node
    for child in node.children:
        yield from _walk(child)


def _bottom(n: _Node) -> tuple[float, float]:
    """Bottom centre of a box."""
    return (n.x + n.w / 2, n.y + n.h)


def _top(n: _Node) -> tuple[float, float]:
    """Top centre of a box."""
    return (n.x + n.w / 2, n.y)


def _edges(node: _Node, pic: Picture) -> None:
    """Parent-child lines, $sequence arrows and $parallel arcs of one node's plot."""
    by_name = {c.name: c for c in node.children}
    for child in node.children:
        pic.paths.append(Path([_bottom(node), _top(child)]))
    _plot_marks(node, node.plot, by_name, pic)


def _plot_marks(node: _Node, plot: Any, by_name: dict, pic: Picture) -> tuple[str, str] | None:
    """Draw a plot's arrows/arcs; return its (first, last) child names."""
    if not isinstance(plot, list) or not plot:
        return None
    if plot[0] == "$action":
        return (plot[1], plot[1]) if plot[1] in by_name else None
    parts = [p for p in (_plot_marks(node, sub, by_name, pic) for sub in plot[1:]) if p]
    if not parts:
        return None
    if plot[0] == "$sequence":
        for (_, a), (b, _) in zip(parts, parts[1:], strict=False):
            na, nb = by_name[a], by_name[b]
            y = min(na.y + na.h / 2, nb.y + nb.h / 2)
            pic.paths.append(Path([(na.x + na.w, y), (nb.x, y)], arrow=True, css="sequence"))
    elif plot[0] == "$parallel" and len(parts) > 1:
        _arc(node, by_name[parts[0][0]], by_name[parts[-1][1]], pic)
    return (parts[0][0], parts[-1][1])


def _arc(node: _Node, first: _Node, last: _Node, pic: Picture) -> None:
    """The $parallel arc across the lines to ``first`` .. ``last`` (Fig. 13's AND arc)."""
    cx, cy = _bottom(node)
    a0 = math.atan2(_top(first)[1] - cy, _top(first)[0] - cx)
    a1 = math.atan2(_top(last)[1] - cy, _top(last)[0] - cx)
    lo, hi = min(a0, a1), max(a0, a1)
    pts = [(cx + ARC_R * math.cos(lo + (hi - lo) * k / 24),
            cy + ARC_R * math.sin(lo + (hi - lo) * k / 24)) for k in range(25)]
    pic.paths.append(Path(pts, css="parallel"))


def plan_picture(plan: dict) -> Picture:
    """Lay out ``plan`` (the plan.json dict) as a tree of boxes, arrows and arcs."""
    root = _build(plan, plan["root"], set())
    _measure(root)
    _place(root, MARGIN, MARGIN)
    nodes = list(_walk(root))
    width = max(n.x + n.w for n in nodes) + MARGIN
    height = max(n.y + n.h for n in nodes) + MARGIN
    pic = Picture(math.ceil(width), math.ceil(height))
    for n in nodes:
        pic.rects.append(Rect(n.x, n.y, n.w, n.h, n.fill, n.name, n.css, n.lines))
        if n.children:
            _edges(n, pic)
    return pic


# -- SVG ----------------------------------------------------------------------------------

# Scoped to the picture: inline in report.html, an SVG <style> applies to the whole page.
_STYLE = (".plan-tree .edge{stroke:#555;fill:none;stroke-width:1}"
          ".plan-tree .sequence{stroke:#1f4fa0;fill:none;stroke-width:1.6}"
          ".plan-tree .parallel{stroke:#b0401a;fill:none;stroke-width:2}"
          ".plan-tree text{font-family:monospace;font-size:12px;fill:#111}"
          ".plan-tree .leaf rect{stroke:#999} .plan-tree .operator rect{stroke:#333}")


def to_svg(pic: Picture) -> str:
    """The picture as a standalone SVG document (ids ``op-NAME`` / ``leaf-NAME``)."""
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{pic.width}" height="{pic.height}" '
           f'viewBox="0 0 {pic.width} {pic.height}" class="plan-tree">',
           '<defs><marker id="arrowhead" markerWidth="8" markerHeight="8" refX="7" refY="4" '
           'orient="auto"><path d="M0,0 L8,4 L0,8 z" fill="#1f4fa0"/></marker></defs>',
           f"<style>{_STYLE}</style>",
           f'<rect width="{pic.width}" height="{pic.height}" fill="white"/>']
    for p in pic.paths:
        pts = " ".join(f"{x:.1f},{y:.1f}" for x, y in p.points)
        head = ' marker-end="url(#arrowhead)"' if p.arrow else ""
        out.append(f'<polyline class="{p.css}" points="{pts}"{head}/>')
    for r in pic.rects:
        prefix = "op" if r.css == "operator" else "leaf"
        out.append(f'<g id={quoteattr(f"{prefix}-{r.ident}")} class="{r.css}">'
                   f'<title>{escape(r.ident)}</title>'
                   f'<rect x="{r.x:.1f}" y="{r.y:.1f}" width="{r.w:.1f}" height="{r.h:.1f}" '
                   f'rx="4" fill="{r.fill}"/>')
        for i, (text, bold) in enumerate(r.lines):
            weight = ' font-weight="bold"' if bold else ""
            out.append(f'<text x="{r.x + PAD:.1f}" y="{r.y + PAD + 10 + i * LINE_H:.1f}"'
                       f'{weight}>{escape(text)}</text>')
        out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


# -- OpenCV image ------------------------------------------------------------------------

def _bgr(hex_color: str) -> tuple[int, int, int]:
    """'#rrggbb' -> (b, g, r)."""
    r, g, b = (int(hex_color[i:i + 2], 16) for i in (1, 3, 5))
    return (b, g, r)


_PATH_COLOR = {"edge": "#555555", "sequence": "#1f4fa0", "parallel": "#b0401a"}


def to_image(pic: Picture, scale: float = 1.0) -> np.ndarray:
    """The picture drawn with OpenCV (BGR uint8), ``scale`` x the SVG's size."""
    w, h = math.ceil(pic.width * scale), math.ceil(pic.height * scale)
    img = np.full((h, w, 3), 255, np.uint8)

    def pt(p: tuple[float, float]) -> tuple[int, int]:
        """A pixel point at the chosen scale."""
        return (round(p[0] * scale), round(p[1] * scale))

    for p in pic.paths:
        color = _bgr(_PATH_COLOR.get(p.css, "#555555"))
        thick = 2 if p.css != "edge" else 1
        pts = np.array([pt(q) for q in p.points], np.int32)
        if p.arrow:
            cv2.arrowedLine(img, pt(p.points[-2]), pt(p.points[-1]), color, thick, cv2.LINE_AA,
                            tipLength=min(0.5, 8.0 / max(1.0, math.dist(*p.points[-2:]))))
        else:
            cv2.polylines(img, [pts], False, color, thick, cv2.LINE_AA)
    font, fs = cv2.FONT_HERSHEY_SIMPLEX, 0.38 * scale
    for r in pic.rects:
        x0, y0 = pt((r.x, r.y))
        x1, y1 = pt((r.x + r.w, r.y + r.h))
        cv2.rectangle(img, (x0, y0), (x1, y1), _bgr(r.fill), -1)
        cv2.rectangle(img, (x0, y0), (x1, y1), (60, 60, 60) if r.css == "operator"
                      else (150, 150, 150), 1)
        for i, (text, bold) in enumerate(r.lines):
            org = pt((r.x + PAD, r.y + PAD + 10 + i * LINE_H))
            cv2.putText(img, text, org, font, fs, (20, 20, 20), 2 if bold else 1, cv2.LINE_AA)
    return img


def png_bytes(plan: dict, scale: float = 1.0) -> bytes:
    """``plan`` drawn as PNG file contents."""
    ok, buf = cv2.imencode(".png", to_image(plan_picture(plan), scale))
    if not ok:  # pragma: no cover - OpenCV always encodes a uint8 image
        raise RuntimeError("PNG encoding failed")
    return buf.tobytes()


def svg_text(plan: dict) -> str:
    """``plan`` drawn as an SVG document."""
    return to_svg(plan_picture(plan))
