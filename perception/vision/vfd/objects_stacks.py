"""Stacks the top view cannot tell from one block (Sec. IX-B3; the object-finder's columns).

A column under a top face is read as one block when it fits a shape. It is
two (or more) when the top view shows at most a thin ring of a lower block and
the column fits no shape, or when it fits one yet the side view shows a seam
across its whole front face: two blocks of one footprint whose pair is as tall
as another shape (two 25 mm cubes and a 25 x 25 x 50 column: helper round 17,
u97). Each seam is a crease line on the front face, drawn where one block's
edge meets the next; a block's own front face has none between its top and
bottom edges.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from perception.vision.vfd import objects_rings as rims
from perception.vision.vfd.objects_columns import Footprint
from perception.vision.vfd.objects_match import STACK_MISMATCH_MM, FoundObject, nearest

SEAM_SAMPLES = (0.2, 0.35, 0.5, 0.65, 0.8)  # across the front face, of its width
FACE_OFF_PX = (1.5, 2.5)  # the front face shows this far above and below a seam
SEAM_WIDTH_MM = 4.0  # ... as wide as the column within this


def seam_across(cam, side: np.ndarray, obj: FoundObject, front: float, z: float) -> bool:
    """Whether a seam crosses the whole front face of column ``obj`` (front at y =
    ``front``) at height ``z``: a crease at every sample across its width, and a front
    face as wide as the column just above and just below it at its middle. A block
    standing in front with its top edge at that line shows its own top face above the
    crease, and the elevated side camera sees it; a wider block above, overhanging the
    front, draws its bottom edge across the face below it (a 60 mm flat on a 40 mm post:
    round 11, 32): no seam."""
    cx, sx = obj.position[0], obj.size[0]
    if not all(rims.crease_at(cam, side, (cx + (f - 0.5) * sx, front, z)) for f in SEAM_SAMPLES):
        return False
    mm = 1.0 / max(1e-6, cam.mm_to_px((cx, front, z)))

    def face(sign: float) -> bool:
        runs = [rims.width_at(cam, side, (cx, front, z + sign * off * mm)) for off in FACE_OFF_PX]
        return any(r is not None and abs(r[0] - sx) <= SEAM_WIDTH_MM for r in runs)
    return face(1.0) and face(-1.0)


def hidden_stack(cam, footprint: Footprint, obj: FoundObject, base: float, front: float,
                 side: np.ndarray, shapes: Mapping[str, Sequence[float]], ring=None, face=None,
                 better: bool = False, x_seen: bool = True, above=None, seamed: bool = False
                 ) -> list[FoundObject] | None:
    """Two stacked blocks where the top view shows at most a thin ring of the lower one.

    The column under the top face is then too tall for any shape. The side view
    shows a crease line across the front at the seam; the lower block's width
    comes from its front face there (or from the ring's outline), and the shape
    database gives the pair that explains the column best. ``better``: only a pair
    that fits the shapes better than the column (a ring that may not be one).
    ``x_seen``: ``obj``'s x is its top face's; else (the lower part of a stack read
    from a ring lifted to the wrong height) the upper block's x comes from its front
    face too. ``seamed``: the column fits a shape as it is; it is a stack only where a
    seam crosses its whole front face (``seam_across``) and the pair fits the shapes.
    """
    sx, sy, sz = obj.size
    if (obj.mismatch < STACK_MISMATCH_MM and ring is None and not seamed) or not shapes:
        return None
    cx, cy = obj.position[:2]
    best = None
    for top_name, (tx, ty, tz) in shapes.items():
        # ``above``: the footprint of a block on this column, which hides a block as
        # wide as it but for a ring too thin to see: only its front face shows how
        # wide it is (a 50 mm slab between 40 mm cubes, helper round 11, 44)
        hidden = above is not None and rims.inside_thin_ring(above, (tx, ty))
        if abs(tx - sx) + abs(ty - sy) <= STACK_MISMATCH_MM:
            tx, ty = sx, sy  # the measured face is the upper block's own
        elif seamed:
            continue  # a seamed column's blocks are as wide as its top face
        elif not hidden and not rims.inside_thin_ring((tx, ty), (sx, sy)):
            continue  # else the face is the outline of thin rings around it
        rest = sz - tz
        seam = base + rest
        if rest < 5.0 or not (seam_across(cam, side, obj, front, seam) if seamed else
                              rims.crease_at(cam, side, (cx, front, seam))):
            continue
        lows = []  # (name, centre x y, size, mismatch, from the ring)
        if ring is not None:  # the lower block's outline is the ring's, or shows in it
            done = rims.complete_rim(footprint(ring, seam), rims.cover_of(
                obj, footprint(face, seam)), (cx, cy), rest, shapes,
                STACK_MISMATCH_MM)
            if done is not None:
                lows.append((done[0], done[1], np.array([*done[2], rest]), done[3], True))
        # Or from the front face's width: halfway up the rest; when that is a seam (the
        # rest is itself two blocks of one height: a user's three-high stack, helper
        # s17) a quarter below the top of the rest, then a quarter above its bottom.
        # Halfway first: a quarter below the top first misread bench 1070's stack at
        # 2x. A ring may be the sliver of a middle block's (bench 3119 at 4x).
        # A row within a pixel of a seam is cut short by its crease (the 40 mm block
        # on a 30 mm one under a 50 mm top read 21 mm: round 13, 07): rows clear of
        # creases first; eighths too, for a rest of four (a five-high stack of equal
        # cubes has a seam at each quarter: round 15, v64d).
        zs = [base + f * rest for f in (0.5, 0.75, 0.25, 0.375, 0.625, 0.125, 0.875)]
        zs.sort(key=lambda z: rims.crease_at(cam, side, (cx, front, z)))
        run = next((r for z in zs if (r := rims.width_at(cam, side, (cx, front, z)))
                    is not None), None)
        if run is not None:
            width, mid = run
            # wider than what the upper block hides from above: its top would show
            c0, d0, c1, d1 = rims.cover_of(obj, footprint(face, seam))
            # a rest no shape is as tall as is a stack itself, split again below:
            # its width alone names it (three 40 mm cubes stacked, generated
            # stacked-start 1012: the two under the top one were called a brick)
            tall = all(abs(v[2] - rest) > STACK_MISMATCH_MM for v in shapes.values())
            # along each axis no wider than a ring too thin to see: a 30 x 40 post
            # under a 40 x 30 lid shows 5 mm strips along y only (generated 5143)
            fits = {n: abs(lx - width) + (0.0 if tall else abs(lz - rest))
                    for n, (lx, ly, lz) in shapes.items()
                    if rims.thin_rings_only((max(sx, c1 - c0), max(sy, d1 - d0)), (lx, ly))}
            if fits:
                n = min(fits, key=fits.get)
                # x from the front face: the upper block may stand off-centre
                lows.append((n, (mid, cy), np.array([width, shapes[n][1], rest]),
                             fits[n], False))
        # The upper block's own front face, halfway up it, must be as wide as it: a
        # face whose outline is a lower block's (its ring merged in) fits both an
        # upper block as wide and one inside the ring (helper v17c: 50, 40 and 30 mm
        # blocks stacked, the middle one named 50 mm)
        up = rims.width_at(cam, side, (cx, front, seam + tz / 2.0)) if lows else None
        for low_name, low_at, low_size, low_err, of_ring in lows:
            if hidden and (tx, ty) != (sx, sy):
                if up is None:
                    continue
                face_err = 0.0  # its front face's width (below) is all there is
            elif not of_ring and (tx, ty) != (sx, sy):
                # The face measured is the thin rings' outer edge, the lower block's
                # outline: that is what it must match, not the upper block hidden
                # inside (a cube in a block's 5 mm ring paid the 10 mm ring twice and
                # lost to a block on a cube: rearrange 1141, 1214).
                face_err = abs(shapes[low_name][0] - sx) + abs(shapes[low_name][1] - sy)
            else:
                face_err = abs(tx - sx) + abs(ty - sy)
            err = face_err + low_err + (abs(up[0] - tx) if up is not None else 0.0)
            if best is None or err < best[0]:
                best = (err, top_name, (tx, ty, tz), low_name, low_size, low_at, seam, up)
    # a seamed pair's error sums three readings (its face, the lower front face and
    # the upper's) where the column's is one: at pixel noise 8 two 40 mm cubes summed 7-9
    if best is None or (seamed and best[0] >= 2.0 * STACK_MISMATCH_MM) or (
            not seamed and (ring is None or better) and best[0] >= obj.mismatch):
        return None
    err, top_name, (tx, ty, tz), low_name, low_size, low_at, seam, up = best
    low = FoundObject(low_name, (float(low_at[0]), float(low_at[1]), base + low_size[2] / 2),
                      tuple(float(v) for v in low_size), err)
    up_x = up[1] if not x_seen and up is not None else cx
    top = FoundObject(top_name, (up_x, cy, seam + tz / 2.0), (tx, ty, base + sz - seam), err)
    # The lower piece may be a stack itself (three blocks, each ring too thin to see):
    # split it again where its own column fits no shape.
    low_fit = nearest(shapes, np.array(low.size))[1]
    # its seams are on its own front face, behind a wider block's above it (two cubes
    # under a slab that overhangs them by 20 mm, helper round 6's e07)
    # A lower piece that fits a shape may still be two blocks of one footprint, seamed.
    deeper = hidden_stack(
        cam, footprint, replace(low, mismatch=low_fit), base,
        max(front, low.position[1] - low.size[1] / 2), side, shapes, None,
        face if ring is None else ring, x_seen=ring is None and x_seen, above=(tx, ty),
        seamed=low_fit < STACK_MISMATCH_MM)
    return [*(deeper or [low]), top]

