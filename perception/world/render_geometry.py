"""Box geometry for the renderer: unit cube tables, rotated corners and normals, face shades.

World side of perception (used by ``perception.world.render``). An axis-aligned box's visible
faces depend only on which side of each pair of face planes the eye is; their union's
outline (``OUTLINE``) is what the renderer fills for a flat-gray box.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from perception.world.scene import Box

# Unit cube corners (index bit 0 -> x, bit 1 -> y, bit 2 -> z) and faces as corner quads.
UNIT = np.array([[(i & 1) * 2 - 1, (i >> 1 & 1) * 2 - 1, (i >> 2 & 1) * 2 - 1]
                  for i in range(8)], dtype=float) / 2.0
FACES = np.array([
    [0, 2, 6, 4],  # -x
    [1, 3, 7, 5],  # +x
    [0, 1, 5, 4],  # -y
    [2, 3, 7, 6],  # +y
    [0, 1, 3, 2],  # -z (bottom)
    [4, 5, 7, 6],  # +z (top)
])
NORMALS = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]], float)


def block_shade(normals: np.ndarray) -> np.ndarray:
    """Gray level of block faces from their unit normals [...,3]: top 255, x 205, y 170."""
    up = np.clip(normals[..., 2], 0.0, 1.0)
    side_x = np.abs(normals[..., 0]) * (1.0 - up)
    return np.clip(170.0 + 85.0 * up + 35.0 * side_x, 0, 255).astype(np.int32)


def face_shade(nx: float, ny: float, nz: float) -> int:
    """``block_shade`` of one unit normal, in plain floats."""
    up = min(max(nz, 0.0), 1.0)
    side_x = abs(nx) * (1.0 - up)
    return int(min(max(170.0 + 85.0 * up + 35.0 * side_x, 0.0), 255.0))


def box_geometry(scene: Sequence[Box]) -> tuple[np.ndarray, np.ndarray]:
    """World corners [N,8,3] and face normals [N,6,3] of the scene's (tilted) boxes."""
    rows = np.array([(*b.center, *b.size, b.angle) for b in scene], float).reshape(-1, 7)
    return geometry(rows)


AXIS_SHADES = block_shade(NORMALS).tolist()


def outline(faces: tuple[int, ...]) -> list[int]:
    """Corner indices around the union of a box's visible ``faces``, padded to six."""
    edges: dict[frozenset, int] = {}
    for f in faces:
        q = FACES[f].tolist()
        for k in range(4):
            e = frozenset((q[k], q[(k + 1) % 4]))
            edges[e] = edges.get(e, 0) + 1
    nbrs: dict[int, list[int]] = {}
    for e, count in edges.items():
        if count == 1:  # an edge shared by two visible faces lies inside the outline
            a, b = tuple(e)
            nbrs.setdefault(a, []).append(b)
            nbrs.setdefault(b, []).append(a)
    cycle = [min(nbrs)]
    prev = None
    while True:
        a, b = nbrs[cycle[-1]]
        nxt = b if a == prev else a
        if nxt == cycle[0]:
            break
        prev = cycle[-1]
        cycle.append(nxt)
    return cycle + cycle[-1:] * (6 - len(cycle))  # a repeated vertex fills nothing more


# Every non-empty set of visible faces of an axis-aligned box (one per axis at most).
OUTLINE = {vis: outline(vis) for vis in
            (tuple(f for f in combo if f >= 0) for combo in
             ((x, y, z) for x in (-1, 0, 1) for y in (-1, 2, 3) for z in (-1, 4, 5)))
            if vis}


def geometry(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Corners and normals from rows (cx, cy, cz, sx, sy, sz, angle)."""
    n = len(rows)
    centers, sizes, angles = rows[:, :3], rows[:, 3:6], rows[:, 6]
    local = UNIT[None, :, :] * sizes[:, None, :]
    if not angles.any():  # the common case: nothing tilted
        return local + centers[:, None, :], np.broadcast_to(NORMALS, (n, 6, 3))
    # A positive angle turns +x towards +z (counter-clockwise in the x-z plane drawn with
    # x right and z up, as pymunk draws its plane).
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    corners = np.empty_like(local)
    corners[..., 0] = c * local[..., 0] - s * local[..., 2]
    corners[..., 1] = local[..., 1]
    corners[..., 2] = s * local[..., 0] + c * local[..., 2]
    normals = np.empty((n, 6, 3))
    normals[..., 0] = c * NORMALS[None, :, 0] - s * NORMALS[None, :, 2]
    normals[..., 1] = NORMALS[None, :, 1]
    normals[..., 2] = s * NORMALS[None, :, 0] + c * NORMALS[None, :, 2]
    return corners + centers[:, None, :], normals
