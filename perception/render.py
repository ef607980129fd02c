"""Rasterizer: a scene of boxes -> the top and side gray images with sensor noise.

World side of perception (it reads ``perception.scene.Box`` lists). Blocks are
white with per-face shading and a dark crease line along their edges, so that
the top face, the side faces and stacked blocks separate in the image; the hand
has its own flat gray level; the table and background are black (footnote 9 of
the paper: the table is painted black). Occlusion uses the painter's algorithm
with a box order derived from separating planes (exact for disjoint axis-aligned
boxes). Gaussian gray-level noise comes from a seeded pool of precomputed noise
images, added with saturating cv2 arithmetic, so a frame costs a few cv2 calls.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import cv2
import numpy as np

from .camera import Camera
from .scene import Box

# Gray levels (documented in docs/vision.md; detectors key their thresholds on them).
BACKGROUND = 0
HAND_GRAY = 128
ARM_GRAY = 80
CREASE_GRAY = 60
_FLAT = {"hand": HAND_GRAY, "arm": ARM_GRAY}

# Unit cube corners (index bit 0 -> x, bit 1 -> y, bit 2 -> z) and faces as corner quads.
_UNIT = np.array([[(i & 1) * 2 - 1, (i >> 1 & 1) * 2 - 1, (i >> 2 & 1) * 2 - 1]
                  for i in range(8)], dtype=float) / 2.0
_FACES = np.array([
    [0, 2, 6, 4],  # -x
    [1, 3, 7, 5],  # +x
    [0, 1, 5, 4],  # -y
    [2, 3, 7, 6],  # +y
    [0, 1, 3, 2],  # -z (bottom)
    [4, 5, 7, 6],  # +z (top)
])
_NORMALS = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]], float)
_SHIFT = 4  # sub-pixel bits for cv2 polygon vertices
_ONE = 1 << _SHIFT
_EPS_MM = 0.5  # boxes closer than this along an axis count as touching (stacked)
_POOL = 24  # precomputed noise images per camera


def block_shade(normals: np.ndarray) -> np.ndarray:
    """Gray level of block faces from their unit normals [...,3]: top 255, x 205, y 170."""
    up = np.clip(normals[..., 2], 0.0, 1.0)
    side_x = np.abs(normals[..., 0]) * (1.0 - up)
    return np.clip(170.0 + 85.0 * up + 35.0 * side_x, 0, 255).astype(np.int32)


def box_geometry(scene: Sequence[Box]) -> tuple[np.ndarray, np.ndarray]:
    """World corners [N,8,3] and face normals [N,6,3] of the scene's (tilted) boxes."""
    n = len(scene)
    centers = np.array([b.center for b in scene], float).reshape(n, 3)
    sizes = np.array([b.size for b in scene], float).reshape(n, 3)
    angles = np.array([b.angle for b in scene], float)
    local = _UNIT[None, :, :] * sizes[:, None, :]
    # A positive angle turns +x towards +z (counter-clockwise in the x-z plane drawn with
    # x right and z up, as pymunk draws its plane).
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    corners = np.empty_like(local)
    corners[..., 0] = c * local[..., 0] - s * local[..., 2]
    corners[..., 1] = local[..., 1]
    corners[..., 2] = s * local[..., 0] + c * local[..., 2]
    normals = np.empty((n, 6, 3))
    normals[..., 0] = c * _NORMALS[None, :, 0] - s * _NORMALS[None, :, 2]
    normals[..., 1] = _NORMALS[None, :, 1]
    normals[..., 2] = s * _NORMALS[None, :, 0] + c * _NORMALS[None, :, 2]
    return corners + centers[:, None, :], normals


def paint_order(lo: np.ndarray, hi: np.ndarray, eye: np.ndarray, bbox: np.ndarray) -> list[int]:
    """Far-to-near drawing order of boxes with bounds [N,3] and image boxes [N,4] from ``eye``."""
    n = len(lo)
    nearest = np.linalg.norm(np.clip(eye, lo, hi) - eye, axis=1)
    order = np.argsort(-nearest, kind="stable")
    if n < 2:
        return order.tolist()
    H, L = hi[:, None, :], lo[None, :, :]
    sep = H <= L + _EPS_MM  # sep[a, b, k]: a lies below b along axis k
    eye_low = eye[None, None, :] < (H + L) / 2.0  # eye on a's side of the separating plane
    front = (sep & eye_low).any(axis=2) | (sep & ~eye_low).any(axis=2).T
    front &= ~front.T  # contradicting planes: the projections cannot overlap
    # Only pairs whose images overlap constrain the order.
    front &= ((bbox[:, None, 0] < bbox[None, :, 2]) & (bbox[None, :, 0] < bbox[:, None, 2])
              & (bbox[:, None, 1] < bbox[None, :, 3]) & (bbox[None, :, 1] < bbox[:, None, 3]))
    ordered = front[np.ix_(order, order)]
    if not np.triu(ordered, 1).any():
        return order.tolist()
    return _topological(order.tolist(), front)


def _topological(order: list[int], front: np.ndarray) -> list[int]:
    """Stable topological sort: a box is drawn after every box it is in front of."""
    remaining = list(order)
    out: list[int] = []
    while remaining:
        for i, a in enumerate(remaining):
            if not any(front[b, a] for b in remaining if b != a):
                out.append(remaining.pop(i))
                break
        else:  # a cycle (interpenetrating boxes): fall back on distance order
            out.append(remaining.pop(0))
    return out


class _Drawn:
    """A box prepared for drawing: bounds, and per camera its visible faces and 2-D bounds."""

    __slots__ = ("lo", "hi", "faces", "creases", "bbox")

    def __init__(self, lo, hi, faces, creases, bbox) -> None:
        """Store the prepared drawing data (see ``Renderer._prepare``)."""
        self.lo, self.hi, self.faces, self.creases, self.bbox = lo, hi, faces, creases, bbox


class Renderer:
    """Render a list of ``Box`` into one uint8 gray image per camera, with pixel noise."""

    def __init__(self, cameras: Mapping[str, Camera], pixel_noise: float = 2.0,
                 seed: int = 0) -> None:
        """Prepare the cameras and a seeded pool of noise images of std ``pixel_noise``."""
        self.cameras = dict(cameras)
        self.pixel_noise = float(pixel_noise)
        self._rng = np.random.default_rng(seed)
        self._noise: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
        if self.pixel_noise > 0:
            for name, cam in self.cameras.items():
                w, h = cam.size
                pool = []
                for _ in range(_POOL):
                    g = np.rint(self._rng.normal(0.0, self.pixel_noise, (h, w)))
                    pool.append((np.clip(g, 0, 255).astype(np.uint8),
                                 np.clip(-g, 0, 255).astype(np.uint8)))
                self._noise[name] = pool
        self._picks = self._rng.integers(0, _POOL, size=4096).tolist()
        self._frame = 0
        self._last_key: tuple[Box, ...] | None = None
        self._last_clean: dict[str, np.ndarray] = {}
        # Static blocks repeat from frame to frame: their projections are computed once.
        self._cache: dict[Box, _Drawn] = {}
        self._blank = {name: np.zeros((c.size[1], c.size[0]), np.uint8)
                       for name, c in self.cameras.items()}

    def render(self, scene: Sequence[Box]) -> dict[str, np.ndarray]:
        """Return ``{"top": img, "side": img}`` for ``scene`` (fresh noise every call)."""
        key = tuple(scene)
        if key != self._last_key:
            self._last_clean = self.render_clean(key)
            self._last_key = key
        if not self._noise:
            return {name: img.copy() for name, img in self._last_clean.items()}
        pick = self._picks[self._frame % len(self._picks)]
        self._frame += 1
        out = {}
        for k, (name, clean) in enumerate(self._last_clean.items()):
            plus, minus = self._noise[name][(pick + 7 * k) % _POOL]
            out[name] = cv2.subtract(cv2.add(clean, plus), minus)
        return out

    def render_clean(self, scene: Sequence[Box]) -> dict[str, np.ndarray]:
        """Noise-free images of ``scene`` for every camera."""
        cache = self._cache
        missing = [b for b in dict.fromkeys(scene) if b not in cache]
        if missing:
            if len(cache) > 4096:  # a long run with a moving hand: forget old poses
                cache.clear()
            cache.update(zip(missing, self._prepare(missing), strict=True))
        drawn = [cache[b] for b in scene]
        images = {}
        if drawn:
            lo = np.array([d.lo for d in drawn])
            hi = np.array([d.hi for d in drawn])
        for name, cam in self.cameras.items():
            img = self._blank[name].copy()
            if drawn:
                bbox = np.array([d.bbox[name] for d in drawn])
                for i in paint_order(lo, hi, cam.center, bbox):
                    d = drawn[i]
                    for quad, color in d.faces[name]:
                        cv2.fillConvexPoly(img, quad, color, cv2.LINE_8, _SHIFT)
                    if d.creases:
                        cv2.polylines(img, d.creases[name], True, CREASE_GRAY, 1,
                                      cv2.LINE_8, _SHIFT)
            images[name] = img
        return images

    def _prepare(self, boxes: list[Box]) -> list[_Drawn]:
        """Project a batch of boxes into every camera and keep their visible faces."""
        corners, normals = box_geometry(boxes)
        n = len(boxes)
        flat = corners.reshape(-1, 3)
        lo, hi = corners.min(axis=1), corners.max(axis=1)
        shades = block_shade(normals)
        for i, b in enumerate(boxes):
            if b.kind in _FLAT:
                shades[i, :] = _FLAT[b.kind]
        face_mid = corners[:, _FACES].mean(axis=2)  # [N,6,3]
        per_cam = {}
        for name, cam in self.cameras.items():
            visible = (((cam.center[None, None, :] - face_mid) * normals).sum(axis=2)
                       > 1e-6).tolist()
            uv = cam.project(flat).reshape(n, 8, 2)
            pix = np.rint(uv * _ONE).astype(np.int32)
            quads = np.ascontiguousarray(pix[:, _FACES])  # [N,6,4,2]
            bb = np.concatenate([uv.min(axis=1), uv.max(axis=1)], axis=1).tolist()
            per_cam[name] = (visible, quads, bb)
        out = []
        for i, b in enumerate(boxes):
            faces, creases, bbox = {}, {}, {}
            for name, (visible, quads, bb) in per_cam.items():
                faces[name] = [(quads[i, f], int(shades[i, f])) for f in range(6)
                               if visible[i][f]]
                creases[name] = [q for q, _ in faces[name]]
                bbox[name] = bb[i]
            out.append(_Drawn(tuple(lo[i]), tuple(hi[i]), faces,
                              creases if b.kind == "block" else None, bbox))
        return out
