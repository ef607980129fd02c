"""Rasterizer: a scene of boxes -> the top and side gray images with sensor noise.

World side of perception (it reads ``perception.world.scene.Box`` lists). Blocks are
white with per-face shading and a dark crease line along their edges, so that
the top face, the side faces and stacked blocks separate in the image; the hand
has its own flat gray level; the table and background are black (footnote 9 of
the paper: the table is painted black). Occlusion uses the painter's algorithm
with a box order derived from separating planes (exact for disjoint axis-aligned
boxes). Gaussian gray-level noise comes from a seeded pool of precomputed noise
images, added with saturating cv2 arithmetic, so a frame costs a few cv2 calls.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import cv2
import numpy as np

from perception.vision.camera import Camera
from perception.world.painter import (
    ARM_GRAY,
    BACKGROUND,
    CREASE_GRAY,
    HAND_GRAY,
    occludes,
    paint_order,
)
from perception.world.painter import FLAT as _FLAT
from perception.world.painter import SHIFT as _SHIFT
from perception.world.painter import Drawn as _Drawn
from perception.world.render_geometry import (
    AXIS_SHADES,
    FACES,
    NORMALS,
    OUTLINE,
    UNIT,
    block_shade,
    box_geometry,
    face_shade,
)
from perception.world.scene import Box

__all__ = ["ARM_GRAY", "BACKGROUND", "CREASE_GRAY", "HAND_GRAY", "Renderer", "block_shade",
           "box_geometry", "occludes", "paint_order"]

_ONE = 1 << _SHIFT
_POOL = 24  # precomputed noise images per camera
_CACHE_SLACK = 64  # prepared boxes kept beyond two frames' worth (see _lookup)
_FLAT_ANGLE = 1e-3  # rad; smaller tilts are drawn untilted (< 0.1 mm at 100 mm, 1/30 px)

_FLAT_SHADES = {kind: [gray] * 6 for kind, gray in _FLAT.items()}
_UNIT_L = [tuple(u) for u in UNIT.tolist()]
_NORMALS_L = [tuple(v) for v in NORMALS.tolist()]


class _Layer:
    """The static blocks of a scene, drawn once per camera, with their occlusion relations."""

    def __init__(self, keys: tuple, items: list[_Drawn], renderer: Renderer) -> None:
        """Draw ``items`` in painter's order for every camera of ``renderer``."""
        self.keys, self.items = keys, items
        self.sheet = renderer._blank.copy()  # every camera's image, stacked (see Renderer)
        self.images = renderer._views(self.sheet)
        self.order: dict[str, list[int]] = {}
        self.hiders: dict[str, list[set[int]]] = {}  # statics drawn over static i (closure)
        for name, cam in renderer.cameras.items():
            img = self.images[name]
            order = paint_order(items, name, cam.center)
            for i in order:
                items[i].draw(img, name)
            hiders: list[set[int]] = [set() for _ in items]
            for pos in range(len(order) - 1, -1, -1):  # near to far builds the closure
                i = order[pos]
                for j in order[pos + 1:]:
                    if occludes(items[j], items[i], name, cam.center) > 0:
                        hiders[i] |= {j} | hiders[j]
            self.order[name], self.hiders[name] = order, hiders


class Renderer:
    """Render a list of ``Box`` into one uint8 gray image per camera, with pixel noise."""

    def __init__(self, cameras: Mapping[str, Camera], pixel_noise: float = 2.0,
                 seed: int = 0) -> None:
        """Prepare the cameras and a seeded pool of noise images of std ``pixel_noise``."""
        self.cameras = dict(cameras)
        self.pixel_noise = float(pixel_noise)
        rng = np.random.default_rng(seed)
        # All cameras' images live stacked in one "sheet" (rows of camera k below those of
        # camera k-1), so copying the static layer and adding noise are one cv2 call each
        # per frame, not one per camera; render() hands out views of the sheet.
        self._rows: dict[str, tuple[int, int, int]] = {}  # name -> (first row, h, w)
        top = 0
        for name, cam in self.cameras.items():
            self._rows[name] = (top, cam.size[1], cam.size[0])
            top += cam.size[1]
        self._blank = np.zeros((top, max(c.size[0] for c in self.cameras.values())), np.uint8)
        self._noise: list[tuple[np.ndarray, np.ndarray]] = []  # (plus, minus) sheets
        if self.pixel_noise > 0:
            pools = {}
            for name, cam in self.cameras.items():
                w, h = cam.size
                pool = []
                for _ in range(_POOL):
                    g = np.rint(rng.normal(0.0, self.pixel_noise, (h, w)))
                    pool.append((np.clip(g, 0, 255).astype(np.uint8),
                                 np.clip(-g, 0, 255).astype(np.uint8)))
                pools[name] = pool
            for p in range(_POOL):  # camera k takes pool image (pick + 7 k) of its own pool
                plus, minus = self._blank.copy(), self._blank.copy()
                for k, name in enumerate(self.cameras):
                    a, b = pools[name][(p + 7 * k) % _POOL]
                    self._views(plus)[name][...] = a
                    self._views(minus)[name][...] = b
                self._noise.append((plus, minus))
        self._picks = rng.integers(0, _POOL, size=4096).tolist()
        self._frame = 0
        self._cache: dict[tuple, _Drawn] = {}  # projections of boxes seen recently
        self._step = 0  # frames composed (for "unchanged since the previous frame")
        self._last_keys: list[tuple] = []
        self._last_clean: np.ndarray | None = None  # the last composed sheet
        # Both projection matrices stacked, so a batch of corners is projected in one product.
        self._names = list(self.cameras)
        self._MT = np.ascontiguousarray(np.vstack([c.P[:, :3] for c in self.cameras.values()]).T)
        self._p4 = np.concatenate([c.P[:, 3] for c in self.cameras.values()])
        # Axis-aligned corner k of camera c is M_c (centre + UNIT[k] * size) + p4_c: linear in
        # (centre, size), so rows (cx, cy, cz, sx, sy, sz, 1) @ _W give h[C, 8, 3] at once.
        self._W = np.concatenate([np.vstack([c.P[:, :3].T, UNIT[k][:, None] * c.P[:, :3].T,
                                             c.P[:, 3]])
                                  for c in self.cameras.values() for k in range(8)], axis=1)
        self._eyes = np.array([c.center for c in self.cameras.values()])
        self._eyes_l = self._eyes.tolist()
        self._layer = _Layer((), [], self)

    def render(self, scene: Sequence[Box]) -> dict[str, np.ndarray]:
        """Return ``{"top": img, "side": img}`` for ``scene`` (fresh noise every call)."""
        # Plain tuples of the fields: hashed and compared in C (a frozen dataclass hashes
        # and compares through Python code, and every frame's boxes are new objects).
        keys = [(b.kind, b.center, b.size, b.angle, b.name) for b in scene]
        if keys != self._last_keys or self._last_clean is None:
            self._last_clean = self._compose(scene, keys)
            self._last_keys = keys
        if not self._noise:
            return self._views(self._last_clean.copy())
        plus, minus = self._noise[self._picks[self._frame % len(self._picks)]]
        self._frame += 1
        out = cv2.add(self._last_clean, plus)
        cv2.subtract(out, minus, dst=out)
        return self._views(out)

    def _views(self, sheet: np.ndarray) -> dict[str, np.ndarray]:
        """Each camera's image inside a stacked ``sheet``."""
        return {name: sheet[r:r + h, :w] for name, (r, h, w) in self._rows.items()}

    def render_clean(self, scene: Sequence[Box]) -> dict[str, np.ndarray]:
        """Noise-free images of ``scene`` for every camera (no layer caching)."""
        keys = [(b.kind, b.center, b.size, b.angle, b.name) for b in scene]
        layer = _Layer((), self._lookup(scene, keys), self)
        return self._views(layer.sheet)

    def _lookup(self, scene: Sequence[Box], keys: list[tuple]) -> list[_Drawn]:
        """The prepared drawing of every box; new ones are projected in one batch."""
        cache = self._cache
        drawn = [cache.get(k) for k in keys]  # one hash per box and frame
        missing = [i for i, d in enumerate(drawn) if d is None]
        if missing:
            if len(cache) > _CACHE_SLACK + 2 * len(keys):
                # Only boxes of the previous frame can be reused (a trembling hand never
                # repeats a pose), so forget the rest often: a large cache of dead poses
                # is what made the cyclic garbage collector cost ~8% of a frame.
                self._cache = cache = {k: d for k, d in cache.items() if d.seen >= self._step - 1}
            fresh = self._prepare([scene[i] for i in missing])
            for i, d in zip(missing, fresh, strict=True):
                cache[keys[i]] = drawn[i] = d
        return drawn

    def _compose(self, scene: Sequence[Box], keys: list[tuple]) -> np.ndarray:
        """Static blocks come from a cached layer; moving boxes are drawn over it."""
        drawn = self._lookup(scene, keys)
        self._step += 1
        step = self._step
        # A block is static when the previous frame had it exactly where it is now.
        static, others = [], []
        for d in drawn:
            if d.kind == "block" and d.seen == step - 1:
                static.append(d)
            else:
                others.append(d)
            d.seen = step
        key = tuple(map(id, static))
        if key != self._layer.keys:
            self._layer = _Layer(key, static, self)
        layer = self._layer
        moving = others  # the layer now holds exactly the static blocks
        sheet = layer.sheet.copy()
        if moving:
            images = self._views(sheet)
            for name, cam in self.cameras.items():
                self._draw_moving(images[name], name, cam.center, layer, moving)
        return sheet

    @staticmethod
    def _draw_moving(img: np.ndarray, name: str, eye: np.ndarray, layer: _Layer,
                     moving: list[_Drawn]) -> None:
        """Paint moving boxes, then repaint the static boxes that hide them (painter's)."""
        order = paint_order(moving, name, eye)
        for i in order:
            moving[i].draw(img, name)
        # Only static boxes whose image meets the moving boxes' joint image can hide them.
        u0, v0, u1, v1 = moving[0].bbox[name]
        for m in moving[1:]:
            a, b, c, d = m.bbox[name]
            u0, v0 = (a if a < u0 else u0), (b if b < v0 else v0)
            u1, v1 = (c if c > u1 else u1), (d if d > v1 else v1)
        hiders: set[int] = set()
        for j, s in enumerate(layer.items):
            p = s.bbox[name]
            if p[0] >= u1 or p[2] <= u0 or p[1] >= v1 or p[3] <= v0:
                continue
            if any(occludes(s, m, name, eye) > 0 for m in moving):
                hiders |= {j} | layer.hiders[name][j]
        if not hiders:
            return
        for j in layer.order[name]:
            if j in hiders:
                layer.items[j].draw(img, name)
        for i in order:  # a moving box in front of a repainted static box comes back on top
            if any(occludes(moving[i], layer.items[j], name, eye) > 0 for j in hiders):
                moving[i].draw(img, name)

    def _prepare(self, boxes: list[Box]) -> list[_Drawn]:
        """Project a batch of boxes into every camera and keep their visible faces."""
        n = len(boxes)
        if n == 0:
            return []
        # A held or resting body wobbles by ~1e-4 rad: far below a pixel, drawn untilted.
        rows = [(*b.center, *b.size, b.angle if abs(b.angle) > _FLAT_ANGLE else 0.0)
                for b in boxes]
        if any(r[6] for r in rows):  # rare (a toppling block): tilted ones on their own
            tilted = [i for i, r in enumerate(rows) if r[6]]
            flat = [i for i, r in enumerate(rows) if not r[6]]
            out: list[_Drawn] = [None] * n  # type: ignore[list-item]
            for i, d in zip(tilted, self._prepare_tilted(
                    [boxes[i] for i in tilted], np.array([rows[i] for i in tilted], float)),
                    strict=True):
                out[i] = d
            for i, d in zip(flat, self._prepare([boxes[i] for i in flat]), strict=True):
                out[i] = d
            return out
        names, eyes = self._names, self._eyes_l
        nc = len(names)
        # Axis-aligned: the corners are linear in (centre, size), so corners and projection
        # fold into one product with a precomputed matrix: h[N, C, 8, 3].
        h = (np.array([r[:6] + (1.0,) for r in rows]) @ self._W).reshape(n, nc, 8, 3)
        uv = h[..., :2] / h[..., 2:3]  # [N,C,8,2]
        corners = np.rint(uv * _ONE).astype(np.int32)  # fixed point, _SHIFT fraction bits
        # Image bounds in one reduction: the minimum of (uv, -uv) is (min uv, -max uv), exactly.
        bounds = np.concatenate((uv, -uv), axis=3).min(axis=2).tolist()  # [N,C,4]
        flat = [b.kind in _FLAT for b in boxes]
        # Shaded blocks: every face quad [N,C,6,4,2]; only the visible ones become views.
        quads = None if all(flat) else np.ascontiguousarray(corners[:, :, FACES])
        # Per box and camera: the faces whose outside the eye is on, and the eye's distance.
        seen, outlines = [], []
        for i in range(n):
            cx, cy, cz, sx, sy, sz, _ = rows[i]
            x0, y0, z0 = cx - sx * 0.5, cy - sy * 0.5, cz - sz * 0.5
            x1, y1, z1 = cx + sx * 0.5, cy + sy * 0.5, cz + sz * 0.5
            per_cam = []
            for c, (ex, ey, ez) in enumerate(eyes):
                # Per axis: the eye below the box (the low face shows), above it, or within.
                if ex < x0:
                    fx, dx = (0,), x0 - ex
                elif ex > x1:
                    fx, dx = (1,), x1 - ex
                else:
                    fx, dx = (), 0.0
                if ey < y0:
                    fy, dy = (2,), y0 - ey
                elif ey > y1:
                    fy, dy = (3,), y1 - ey
                else:
                    fy, dy = (), 0.0
                if ez < z0:
                    fz, dz = (4,), z0 - ez
                elif ez > z1:
                    fz, dz = (5,), z1 - ez
                else:
                    fz, dz = (), 0.0
                vis = fx + fy + fz
                per_cam.append((vis, math.sqrt(dx * dx + dy * dy + dz * dz)))
                if flat[i] and vis:
                    base = (i * nc + c) * 8
                    outlines.append([base + j for j in OUTLINE[vis]])
            seen.append(((x0, y0, z0), (x1, y1, z1), per_cam))
        # A flat-gray box is one convex polygon, its outline: the same pixels as its faces
        # one by one (checked on 8000 random boxes), in one fill instead of two or three.
        polys = list(corners.reshape(-1, 2)[np.array(outlines, np.intp)]) if outlines else []
        out, p = [], 0
        for i, b in enumerate(boxes):
            lo, hi, per_cam = seen[i]
            faces, bbox, dist = {}, {}, {}
            for c, name in enumerate(names):
                vis, dist[name] = per_cam[c]
                u0, v0, u1, v1 = bounds[i][c]
                bbox[name] = [u0, v0, -u1, -v1]
                if not flat[i]:
                    q = quads[i, c]
                    faces[name] = [(q[f], AXIS_SHADES[f]) for f in vis]
                elif vis:
                    faces[name] = [(polys[p], _FLAT[b.kind])]
                    p += 1
                else:
                    faces[name] = []
            creases = ({name: [q for q, _ in faces[name]] for name in names}
                       if b.kind == "block" else None)
            out.append(_Drawn(b.kind, lo, hi, faces, creases, bbox, dist))
        return out

    def _prepare_tilted(self, boxes: list[Box], rows: np.ndarray) -> list[_Drawn]:
        """``_prepare`` for a batch with a tilted box: corners and normals rotated.

        The geometry of ``render_geometry.geometry`` in plain floats (the same operations,
        so the same values): a batch is usually one held block, where a dozen small numpy
        calls cost more than the arithmetic. Only the projection stays one numpy product.
        """
        n, names, eyes = len(boxes), self._names, self._eyes_l
        cos_l, sin_l = np.cos(rows[:, 6]).tolist(), np.sin(rows[:, 6]).tolist()
        pts: list[tuple[float, float, float]] = []
        geo = []
        for i, (cx, cy, cz, sx, sy, sz, _) in enumerate(rows.tolist()):
            c, s = cos_l[i], sin_l[i]
            # A positive angle turns +x towards +z (see render_geometry.geometry).
            corners = [(c * (ux * sx) - s * (uz * sz) + cx, uy * sy + cy,
                        s * (ux * sx) + c * (uz * sz) + cz) for ux, uy, uz in _UNIT_L]
            pts += corners
            normals = [(c * nx - s * nz, ny, s * nx + c * nz) for nx, ny, nz in _NORMALS_L]
            halfs = (sx / 2.0 + 1e-6, sy / 2.0 + 1e-6, sz / 2.0 + 1e-6)
            # Visible when the eye lies beyond the face plane: n.(eye - c) > half-size.
            vis = []
            for ex, ey, ez in eyes:
                dx, dy, dz = ex - cx, ey - cy, ez - cz
                vis.append([nx * dx + ny * dy + nz * dz > halfs[f >> 1]
                            for f, (nx, ny, nz) in enumerate(normals)])
            xs, ys, zs = zip(*corners, strict=True)
            geo.append(((min(xs), min(ys), min(zs)), (max(xs), max(ys), max(zs)), normals, vis))
        h = (np.array(pts) @ self._MT + self._p4).reshape(n, 8, len(names), 3)
        uv = h[..., :2] / h[..., 2:3]  # [N,8,C,2]
        quads = np.ascontiguousarray(
            np.rint(uv * _ONE).astype(np.int32).transpose(2, 0, 1, 3)[:, :, FACES])
        # (min uv, -max uv) over the corners in one reduction, exactly.
        bounds = np.concatenate((uv, -uv), axis=3).min(axis=1).tolist()  # [N,C,4]
        out = []
        for i, b in enumerate(boxes):
            a, z, normals, vis = geo[i]
            # block_shade of each face, in plain floats (the same operations, per face).
            shade = _FLAT_SHADES.get(b.kind) or [face_shade(*nrm) for nrm in normals]
            faces, bbox, dist = {}, {}, {}
            for c, name in enumerate(names):
                faces[name] = [(quads[c, i, f], shade[f]) for f in range(6) if vis[c][f]]
                u0, v0, u1, v1 = bounds[i][c]
                bbox[name] = [u0, v0, -u1, -v1]
                e = eyes[c]  # distance from the eye to the nearest point of the box
                d0 = min(max(e[0], a[0]), z[0]) - e[0]
                d1 = min(max(e[1], a[1]), z[1]) - e[1]
                d2 = min(max(e[2], a[2]), z[2]) - e[2]
                dist[name] = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            creases = ({name: [q for q, _ in faces[name]] for name in names}
                       if b.kind == "block" else None)
            out.append(_Drawn(b.kind, a, z, faces, creases, bbox, dist))
        return out
