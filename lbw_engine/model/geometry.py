"""Axis-aligned box geometry, and the one definition of "what rests on what".

Support is read from boxes the way the paper's environment model states it
(Sec. V-B4): an object rests on the table when its bottom is at z = 0, and on
the objects whose top faces meet its bottom face over a common footprint. The
same test serves every part of lbw that needs it — the initial state the
object-finder measured, a place in the recognizer's environment model,
execution's expected state and its verification, and the simulated world's
ground truth — so recognition, execution and evaluation mean the same thing.
Its tolerances are those of camera measurements (a few mm); exact boxes meet
them trivially.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from lbw_engine.names import TABLE

Vec = tuple[float, float, float]
Box = tuple[Vec, Vec]  # (centre, size)

TABLE_X = (-300.0, 300.0)  # the table top's extent, mm (design.md), for everything in lbw
TABLE_Y = (0.0, 400.0)
SUPPORT_GAP_MM = 10.0  # a bottom face this close to a top face can rest on it
SUPPORT_LEVEL_MM = 5.0  # the supports of one object have tops this close to the nearest one
SUPPORT_OVERLAP_MM = 3.0  # ... and footprints overlapping its own by more than this


def overlap(c1: Vec, s1: Vec, c2: Vec, s2: Vec, tol: float = 1.0) -> bool:
    """Do two boxes interpenetrate by more than ``tol`` mm along every axis? (A negative
    ``tol`` asks whether they come within -``tol`` of each other on every axis.)"""
    return _least_overlap(c1, s1, c2, s2) > tol


def depth(c1: Vec, s1: Vec, c2: Vec, s2: Vec) -> float:
    """How deep two boxes interpenetrate: the least of their overlaps along the three
    axes (mm); 0 when they are apart or touch."""
    return max(0.0, _least_overlap(c1, s1, c2, s2))


def _least_overlap(c1: Vec, s1: Vec, c2: Vec, s2: Vec) -> float:
    """The least, over the three axes, of how much two boxes overlap (negative: apart)."""
    return min((float(s1[k]) + float(s2[k])) / 2 - abs(float(c1[k]) - float(c2[k]))
               for k in range(3))


def footprints_meet(c1: Vec, s1: Vec, c2: Vec, s2: Vec, tol: float = SUPPORT_OVERLAP_MM) -> bool:
    """Do the x-y footprints of two boxes share more than ``tol`` mm along x and y?"""
    return all((s1[k] + s2[k]) / 2 - abs(c1[k] - c2[k]) > tol for k in range(2))


def within_along(c: Vec, s: Vec, outer_c: Vec, outer_s: Vec, axis: int,
                 slack: float = 0.0) -> bool:
    """Does box (c, s) stay within box (outer_c, outer_s) along ``axis``, on either
    side, but for ``slack`` mm? (A rider inside the block it rides on: the jaws closing
    along ``axis`` meet the block, not it.)"""
    return abs(c[axis] - outer_c[axis]) + s[axis] / 2 <= outer_s[axis] / 2 + slack


def tilted(c: Vec, s: Vec, angle: float) -> Box:
    """The axis-aligned bounds of a box turned by ``angle`` (rad) in the x-z plane."""
    ca, sa = abs(math.cos(angle)), abs(math.sin(angle))
    return c, (s[0] * ca + s[2] * sa, s[1], s[0] * sa + s[2] * ca)


def tilt(angle: float, s: Vec, square_mm: float = 1.0) -> float:
    """How much (rad) a box turned by ``angle`` in the x-z plane is off looking upright.
    Turned by pi it fills its upright box again; with a square x-z section (within
    ``square_mm``) so it does turned by pi/2: a cube that rolled onto another face stands
    (fault bench seed 5006: a displaced cube rolled a quarter turn onto its plank, and
    the simulator's check called the finished structure toppled)."""
    period = math.pi / 2.0 if abs(s[0] - s[2]) <= square_mm else math.pi
    a = math.fmod(abs(angle), period)
    return min(a, period - a)


def top(c: Vec, s: Vec) -> float:
    """z of a box's top face."""
    return c[2] + s[2] / 2


def resting_on(name: str, boxes: Mapping[str, Box], ignore: frozenset[str] = frozenset(),
               overlap: float = SUPPORT_OVERLAP_MM) -> list[str]:
    """What ``name`` rests on: ``[table]``, the objects under it, or ``[]`` (held, falling).

    Candidates are the table and every box (not in ``ignore``) whose footprint meets
    this one's by more than ``overlap`` mm and whose top is within SUPPORT_GAP_MM of
    its bottom; the nearest top wins, with every other candidate whose top is level
    with it (a multi-support place). Choosing the nearest keeps a block on a 10 mm
    plate off the table.
    """
    c, s = boxes[name]
    bottom = c[2] - s[2] / 2
    gaps = [(abs(bottom), TABLE)] if abs(bottom) <= SUPPORT_GAP_MM else []
    for other, (c2, s2) in boxes.items():
        if other == name or other in ignore:
            continue
        gap = abs(top(c2, s2) - bottom)
        if gap <= SUPPORT_GAP_MM and footprints_meet(c, s, c2, s2, overlap):
            gaps.append((gap, other))
    if not gaps:
        return []
    nearest = min(g for g, _ in gaps)
    return sorted(n for g, n in gaps if g <= nearest + SUPPORT_LEVEL_MM)


def support_relations(boxes: Mapping[str, Box], single: str, multiple: str,
                      overlap: float = SUPPORT_OVERLAP_MM
                      ) -> dict[str, tuple[str, tuple[str, ...]]]:
    """Each object's support relation: (single, (x,)) or (multiple, (x, y, ...)).

    ``single`` and ``multiple`` are the support relations of the rules
    (rules/effects.yaml ``roles``). Objects resting on nothing (held, falling,
    toppled against something) get no entry.
    """
    out = {}
    for name in boxes:
        under = resting_on(name, boxes, overlap=overlap)
        if len(under) == 1:
            out[name] = (single, (under[0],))
        elif under:
            out[name] = (multiple, tuple(under))
    return out
