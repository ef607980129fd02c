"""Small helpers the report's inline SVG pictures share: escaping, colours, legends."""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from typing import Any

# Tableau 10: distinguishable, and readable under white text.
PALETTE = ("#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1",
           "#ff9da7", "#9c755f", "#bab0ac")
SVG_NS = "http://www.w3.org/2000/svg"


def esc(text: Any) -> str:
    """HTML/XML-escaped text (quotes too: safe in attributes)."""
    return html.escape(str(text), quote=True)


def colors(names: Iterable[str], ordered: bool = False) -> dict[str, str]:
    """A stable colour per name: sorted names (or names in the given order) take turns."""
    seq = list(dict.fromkeys(names)) if ordered else sorted(set(names))
    return {n: PALETTE[i % len(PALETTE)] for i, n in enumerate(seq)}


def legend(items: Sequence[tuple[str, str]], ident: str, title: str = "") -> str:
    """An HTML legend: one swatch and name per (name, colour), in the given order."""
    head = f"<b>{esc(title)}</b> " if title else ""
    cells = "".join(f'<span class="key" data-name="{esc(n)}"><i style="background:{c}"></i>'
                    f"{esc(n)}</span>" for n, c in items)
    return f'<div class="legend" id="{esc(ident)}">{head}{cells}</div>'


def text_fits(text: str, width: float, px_per_char: float = 6.2) -> bool:
    """Whether ``text`` in the pictures' 10 px monospace fits in ``width`` px."""
    return width >= px_per_char * len(text) + 4


def time_ticks(t_max: float, x0: float, px_per_s: float, y: float, every_s: int) -> list[str]:
    """A time axis under a timeline: a tick and its label every ``every_s`` seconds."""
    out = []
    for s in range(0, int(t_max) + 1, every_s):
        x = x0 + s * px_per_s
        out.append(f'<line x1="{x}" y1="{y}" x2="{x}" y2="{y + 5}" '
                   f'stroke="#555"/><text x="{x + 2}" y="{y + 16}">{s}s</text>')
    return out
