"""Where a placed block stands along x, from the change-detector's last judgement; the
known boxes it is judged against.

Helpers of ``perception.vision.envnodes.change`` (the SilDiff ENV-node): the side
camera fixes x of a place well, but the changed area's centre carries biases that
the block's projected outline (``side_extent_x``) or the release point
(``placed_x``) can correct, each checked against the image.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.model.geometry import SUPPORT_OVERLAP_MM, depth, footprints_meet
from lbw_engine.names import TABLE
from lbw_engine.see.detectors import ActView
from perception.vision.camera import Camera
from perception.vision.envnodes.hand import box
from perception.vision.vfd.base import (
    BLOCK_MIN,
    Region3D,
    region_mask,
    regions_mask,
    visible_outline,
)
from perception.vision.vfd.change import ChangeDetector, Snapshot

# A placed block's x: the changed area's centre and the release point disagreeing by more
# than FIT_SLACK_MM are checked against the image; the release point needs a block-pixel
# fraction FIT_MARGIN higher to win (see placed_x).
FIT_SLACK_MM, FIT_MARGIN = 10.0, 0.05
INTO_MM = 3.0  # boxes overlapping this much on every axis cannot both be there
EXTENT_SLACK_MM = 4.0  # the side view's changed columns span the placed block's length
KNOWN_MM = 3.0  # a known object's outline grown by the model's error (unknown_top)
MIN_SEEN = 0.2  # a block less visible than this from the side is not placed by what shows
CO_SUPPORT_SHARE = 0.25  # of its side a block set down shares with a co-support it was not
CO_LEVEL_MM = 5.0  # coming over; whose top is this level with its support's
BESIDE_MM = 5.0  # a target whose top is this far above a set-down block's bottom is beside it
NEIGHBOUR_MM = 1.0  # a target the set-down footprint shares less than this with is beside it
LEVEL_MM = 12.0  # tops this close are one level (a support is never thinner than 10 mm)
CENTRED_MM = 8.0  # a set-down point this near its supports' joint centre was meant there
SETTLE_MM = 20.0  # a held block's bottom this near its target's top has come down onto it


def side_extent_x(det: ChangeDetector, cam: Camera, x: float, yz: tuple[float, float],
                  size: Sequence[float]) -> float:
    """x of a placed block whose outline, projected into the side view by ``cam``, spans
    the columns the change spans (``det``'s last judgement), if the two spans are as
    wide (the block's whole outline changed: nothing beside it changed too, nothing hid
    an end).

    The changed area's centre is biased where the block covers pixels that were
    bright already: set down off its support's centre (a staircase step), its front
    face hides part of the support's top face, and the centre moved 5 mm toward the
    overhang (a user's 15 mm step). The face's upper rows still change along its whole
    length. The camera's perspective shows one side face too, so the span is matched
    with the projected box (its eight corners), not read as the block's ends.
    """
    ext = det.extent.get("side")
    if ext is None or not det.appeared.get("side"):
        return x  # the side view's change is not the block appearing
    seen = (ext[0] - 0.5, ext[1] + 0.5)  # the changed columns' outer pixel edges
    half = np.asarray(size, float) / 2.0
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    fitted = x
    for _ in range(2):  # the projection is nearly affine over a few mm: two steps
        u = cam.project(np.array([fitted, yz[0], yz[1]]) + corners * half)[:, 0]
        span = float(u.max() - u.min())
        if abs((seen[1] - seen[0]) - span) > EXTENT_SLACK_MM * span / float(size[0]):
            return x
        fitted += ((seen[0] + seen[1]) - float(u.max() + u.min())) / 2.0 * \
            float(size[0]) / span
    # the centroid's biases are a few mm; a larger move means the span is something else
    return fitted if abs(fitted - x) <= FIT_SLACK_MM else x


def unhidden_x(det: ChangeDetector, cam: Camera, x: float, yz: tuple[float, float],
               size: Sequence[float], front: Sequence[Region3D]) -> float:
    """x of a placed block part of which known objects in front hide from the side camera:
    where the centre of its outline's visible part falls on the changed area's centre.

    Only the visible part can change, so the changed area's centre lies off the block's
    centre, away from what hides it: the last cube of a row set down behind an arch's
    pillar changed 6 of its 14 columns and was measured 13 mm off (bench 1219).
    """
    centre = det.centres.get("side")
    (window,) = det.windows["side"]
    if centre is None or not det.appeared.get("side") or not front:
        return x
    hidden = regions_mask(cam, front, window)
    fitted = x
    for _ in range(3):  # the projection is nearly affine over a few mm
        outline = region_mask(cam, Region3D.around((fitted, *yz), size), window)
        seen = outline & ~hidden
        if not outline.any() or seen.sum() == outline.sum():
            break  # nothing hides it (any more)
        if seen.sum() < MIN_SEEN * outline.sum():
            return x  # too little is left to place it by
        cols = np.nonzero(outline.any(axis=0))[0]
        span = float(cols[-1] - cols[0] + 1) * window.step
        u = window.x0 + (float(np.nonzero(seen)[1].mean()) + 0.5) * window.step - 0.5
        fitted += (centre[0] - u) * float(size[0]) / span
    return fitted if abs(fitted - x) <= float(size[0]) / 2.0 else x


def placed_x(det: ChangeDetector, cameras: Mapping[str, Camera], changed: float,
             released: float, yz: tuple[float, float], size: Sequence[float],
             last: Snapshot, others: Sequence[Region3D]) -> float:
    """x of a placed block: the changed area's centre, unless the release point fits better.

    The changed area's centre is biased when part of the block lands in front of
    something that was already bright (a block behind it, its support's face): those
    pixels did not change. The hand's release point plus the grip offset has no such
    bias, but tremor and tracker errors go straight into it (8-10 mm at 4x noise,
    where the centre is within 1 mm). When the two disagree by more than
    FIT_SLACK_MM, each candidate's box is checked against the end snapshot: the
    fraction of its outline that shows a block, where nothing else can be seen instead
    (the hand, the ``others`` known objects: a pillar standing in front of the spot is
    bright over both candidates, bench 1219); the release point wins only when it
    explains the image clearly better.
    """
    # a candidate whose box would go into a known block is no place a block can be: in a
    # 2 x 2 grid 7 mm apart the side view's change lay between two columns, 21 mm off,
    # 15 mm into the neighbour (generated gaps 1085 at 2x); 12 mm pins 1 mm apart, the
    # change lay 9.5 mm from the release, on the pin beside (helper round 18, r29)
    deep = [max((depth((x, *yz), size, o.center, o.size) for o in others), default=0.0)
            for x in (changed, released)]
    inside = [d > INTO_MM for d in deep]
    if inside[0] != inside[1]:
        return released if inside[0] else changed
    if all(inside) and abs(deep[0] - deep[1]) > INTO_MM:
        # both into a neighbour measured a few mm off: the shallower (the same pins, a
        # seed where the release point lay 3.4 mm into it and the change 10.9 mm)
        return released if deep[1] < deep[0] else changed
    if abs(changed - released) <= FIT_SLACK_MM:
        return changed
    fits = []
    for x in (changed, released):
        region = Region3D.around((x, yz[0], yz[1]), size)
        seen = total = 0
        for view, (window,) in det.windows.items():
            img = last.pixels[view]
            _, mask = visible_outline(cameras[view], region, window, img, others)
            total += int(mask.sum())
            seen += int((mask & (img >= BLOCK_MIN)).sum())
        fits.append(seen / total if total else 0.0)
    return released if fits[1] > fits[0] + FIT_MARGIN else changed


def beside_target(env: EnvModel, targets: Sequence[EnvNode], xy: Sequence[float],
                  size: Sequence[float], bottom: float, moving: set[str]) -> tuple[str, ...]:
    """What a block set down at ``xy`` with its bottom at ``bottom`` rests on, when its
    footprint plainly misses some of the motion's ``targets`` (those it meets, or what is
    under it when it misses all) or plainly rests on a block of their level too; () when
    it meets them all and no other (the :Near search's choice stands).

    The search at :Near takes what lies under the held block then, grown by a margin: a
    brick set down 2 mm north of another along y was put "on" it (helper round 4, v24b),
    though it ended beside it with its bottom at table height. What rests under the
    footprint at the highest level the bottom reaches is the support; nothing: the table.
    """
    def under(n: EnvNode) -> bool:  # footprints sharing SUPPORT_OVERLAP_MM (3 mm) both ways
        return footprints_meet(xy, size, n.position, n.size)

    if not targets:
        return ()
    # Grown by its margin, the held block also reaches a neighbour a few mm beside its
    # support (a staircase on a row with 2 mm gaps, helper round 7's u09 and u21: a step
    # put on b was read as put on a, b and c). Set down, it shares nothing with it.
    # Nor is it on a target whose top stands above where it came down (10 mm cubes laid in
    # a row touching, helper round 8's v14: 1.2 mm of a neighbour's footprint, measured,
    # but the block's bottom at the table, 10 mm under the neighbour's top).
    low = float(xy[2]) - float(size[2]) / 2.0 + BESIDE_MM if len(xy) > 2 else np.inf
    meet = [n for n in targets if footprints_meet(xy, size, n.position, n.size, NEIGHBOUR_MM)
            and n.top() <= low]
    if meet:
        # and the other way: coming in over one cube of a pyramid's row, the hand had the
        # search name that one alone; set down across it and the next, the block shares a
        # quarter of its side with each (lbw bench 1144, a pyramid along y)
        top, skip = max(n.top() for n in meet), {n.name for n in targets} | moving
        # ... or a block of their level centred in their joint footprint that it meets at all:
        # the fourth leg of a table whose plate was carried in over three (legs 7 mm under
        # the plate's edges, each 0.23 of its side; generated 1032 at 4x)
        more = [n for n in env.objects() if n.name not in skip and n.position is not None
                and n.size is not None and abs(n.top() - top) <= CO_LEVEL_MM
                and (_shares(xy, size, n.position, n.size, CO_SUPPORT_SHARE) or
                     footprints_meet(xy, size, n.position, n.size, NEIGHBOUR_MM) and
                     _within(n, targets))]
        if len(meet) < len(targets) and (not _carries(meet + more, xy) and
                                         _carries(targets, xy) or _centred(targets, xy, size)):
            # its centre off the ones it meets, it could not stand on them: the set-down
            # point is off (a 120 mm plate measured 18 mm off its four legs under its
            # edges, generated 1186), not the search; so too where it lies within the
            # measuring error of the centre of all of them, where a load goes
            return ()
        if len(meet) < len(targets) or more:
            return tuple(n.name for n in meet + more)
        return ()
    below = [n for n in env.objects() if n.name not in moving and n.position is not None
             and n.size is not None and under(n) and n.top() <= bottom + LEVEL_MM]
    if not below:
        return (TABLE,)
    level = max(n.top() for n in below)
    return tuple(n.name for n in below if n.top() >= level - LEVEL_MM)


def onto(targets: Sequence[EnvNode], pos: np.ndarray, size: Sequence[float]) -> np.ndarray:
    """``pos`` moved (x, y) the least that lets a footprint of ``size`` meet every target's
    (``footprints_meet``), when the search's targets stand against a set-down point that
    missed some (``beside_target``); as it is when it meets them all or none can."""
    out = np.array(pos, float)
    targets = [t for t in targets if t.position is not None and t.size is not None]
    for k in (0, 1) if targets else ():
        reach = [(float(t.size[k]) + float(size[k])) / 2 - SUPPORT_OVERLAP_MM - 0.5
                 for t in targets]
        lo = max(float(t.position[k]) - r for t, r in zip(targets, reach, strict=True))
        hi = min(float(t.position[k]) + r for t, r in zip(targets, reach, strict=True))
        if lo <= hi:
            out[k] = min(max(out[k], lo), hi)
    return out


def _centred(nodes: Sequence[EnvNode], xy: Sequence[float], size: Sequence[float]) -> bool:
    """Whether ``nodes``, one level, would all carry a load of ``size`` centred on their
    joint footprint, and ``xy`` lies within CENTRED_MM of that centre: a plate set down on
    four legs under its edges by 7 mm, measured 5 mm off along x, met three by more than
    NEIGHBOUR_MM and the fourth by 0.8 mm (generated 1148 at 2x, 1032 at 4x)."""
    if max(n.top() for n in nodes) - min(n.top() for n in nodes) > CO_LEVEL_MM:
        return False
    lo, hi = _joint(nodes)
    mid = (lo + hi) / 2.0
    return float(np.hypot(*(mid - np.asarray(xy[:2], float)))) <= CENTRED_MM and all(
        footprints_meet(mid, size, n.position, n.size, NEIGHBOUR_MM) for n in nodes)


def _within(node: EnvNode, nodes: Sequence[EnvNode]) -> bool:
    """Whether ``node``'s centre lies within the joint footprint of ``nodes`` (a corner
    block's own footprint reaches past it by its measuring error)."""
    return _carries(nodes, node.position)


def _carries(nodes: Sequence[EnvNode], xy: Sequence[float]) -> bool:
    """Whether a load centred at ``xy`` (x, y) lies over the joint footprint of ``nodes``."""
    lo, hi = _joint(nodes)
    return bool(np.all(lo <= np.asarray(xy[:2])) and np.all(np.asarray(xy[:2]) <= hi))


def _joint(nodes: Sequence[EnvNode]) -> tuple[np.ndarray, np.ndarray]:
    """The joint footprint of ``nodes``: its lowest and highest (x, y)."""
    lo = np.min([np.asarray(n.position[:2]) - np.asarray(n.size[:2]) / 2 for n in nodes], axis=0)
    hi = np.max([np.asarray(n.position[:2]) + np.asarray(n.size[:2]) / 2 for n in nodes], axis=0)
    return lo, hi


def _shares(c1: Sequence[float], s1: Sequence[float], c2: Sequence[float],
            s2: Sequence[float], share: float) -> bool:
    """Whether two footprints overlap by ``share`` of the narrower one along x and y."""
    return all(min(c1[k] + s1[k] / 2, c2[k] + s2[k] / 2) - max(c1[k] - s1[k] / 2,
                                                                 c2[k] - s2[k] / 2)
               >= share * min(s1[k], s2[k]) for k in (0, 1))


def targets_of(act: ActView, env: EnvModel) -> list[EnvNode]:
    """The motion's target blocks whose box the environment model knows."""
    return [n for n in env.get(act.target) if n.kind == "Loc" and n.position is not None
            and n.size is not None]


def known_boxes(env: EnvModel) -> list[Region3D]:
    """Boxes of the located objects not held, grown by the model's error (KNOWN_MM)."""
    return [b.grown(KNOWN_MM) for b in boxes_but(env, set(env.held()))]


def boxes_but(env: EnvModel, names: set[str]) -> list[Region3D]:
    """Boxes of the located objects not named in ``names``."""
    return [box(n) for n in env.objects() if n.name not in names and n.position is not None
            and n.size is not None]


def nearer(depth: float, env: EnvModel, but: frozenset | set = frozenset()) -> list[Region3D]:
    """Boxes of known objects (not ``but``, not held) nearer the side camera than y=depth."""
    return [b for b in boxes_but(env, set(but) | set(env.held())) if b.hi[1] <= depth]


def settled(a: Region3D, act: ActView, env: EnvModel) -> Region3D:
    """The held block's box ``a``, set on the motion's target if it has come down to it.

    The box hangs under the hand at the grip measured when it was picked up, and the
    height of both carries the fingertips' error: 5-15 mm when the jaws close across the
    side camera's line of sight (align bench 1009: the bottom 12 mm above the table at
    the release). Faces are side by side only at one level, so the level comes from
    what the block is put on instead.
    """
    tops = [env.nodes[n].top() for n in act.target if n in env.nodes]
    if not tops:
        return a
    dz = max(tops) - float(a.lo[2])
    return a.shifted(dz=dz) if abs(dz) <= SETTLE_MM else a
