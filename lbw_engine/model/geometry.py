"""Axis-aligned box geometry shared by tracing and verification.

Support is read from geometry the way the paper's environment model states it
(Sec. V-B4): an object rests on the table when its bottom is at z = 0, and on
the objects whose top faces meet its bottom face over a common footprint.
"""

from __future__ import annotations

from collections.abc import Mapping

Vec = tuple[float, float, float]
TABLE = "table"  # reserved name of the worktable (design.md)


def overlap(c1: Vec, s1: Vec, c2: Vec, s2: Vec, tol: float = 1.0) -> bool:
    """Do two boxes interpenetrate by more than ``tol`` mm along every axis?"""
    return all(
        (s1[k] + s2[k]) / 2 - abs(c1[k] - c2[k]) > tol for k in range(3)
    )


def footprints_meet(c1: Vec, s1: Vec, c2: Vec, s2: Vec, tol: float = 1.0) -> bool:
    """Do the x-y footprints of two boxes share more than ``tol`` mm along x and y?"""
    return all((s1[k] + s2[k]) / 2 - abs(c1[k] - c2[k]) > tol for k in range(2))


def resting_on(name: str, boxes: Mapping[str, tuple[Vec, Vec]], tol: float = 3.0) -> list[str]:
    """What ``name`` rests on: ``[table]`` or the objects whose tops meet its bottom."""
    c, s = boxes[name]
    bottom = c[2] - s[2] / 2
    if abs(bottom) <= tol:
        return [TABLE]
    out = []
    for other, (c2, s2) in boxes.items():
        if other == name:
            continue
        if abs(c2[2] + s2[2] / 2 - bottom) <= tol and footprints_meet(c, s, c2, s2):
            out.append(other)
    return sorted(out)


def support_relations(
    boxes: Mapping[str, tuple[Vec, Vec]], single: str, multiple: str, tol: float = 3.0
) -> dict[str, tuple[str, tuple[str, ...]]]:
    """Each object's support relation: (single, (x,)) or (multiple, (x, y, ...)).

    ``single`` and ``multiple`` are the relation names from the rules
    (``support_relations`` in commands.yaml). Objects resting on nothing
    (held, falling, toppled against something) get no entry.
    """
    out = {}
    for name in boxes:
        under = resting_on(name, boxes, tol)
        if len(under) == 1:
            out[name] = (single, (under[0],))
        elif under:
            out[name] = (multiple, tuple(under))
    return out


def top(c: Vec, s: Vec) -> float:
    """z of a box's top face."""
    return c[2] + s[2] / 2
