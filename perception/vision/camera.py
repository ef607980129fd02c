"""Pinhole camera models: forward projection, view lines and stereo triangulation.

The paper keeps calibrated left/right camera models that every VFD shares
(Fig. 2, Sec. III-A); here the pair is a top view and an elevated side view of
the same workspace. A camera is a 3x4 projection matrix P = K [R | -R C]
mapping homogeneous world millimetres to pixels (u = column, v = row).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

# Workspace of design.md: table x in [-300, 300], y in [0, 400]; structures below z = 300.
WORKSPACE_LO = np.array([-300.0, 0.0, 0.0])
WORKSPACE_HI = np.array([300.0, 400.0, 300.0])


class Camera:
    """A calibrated perspective camera (world mm -> pixels)."""

    def __init__(self, P: np.ndarray, size: tuple[int, int] = (256, 256), name: str = "") -> None:
        """Wrap a 3x4 projection matrix for images of ``size`` = (width, height)."""
        self.P = np.asarray(P, dtype=float).reshape(3, 4)
        self.size = (int(size[0]), int(size[1]))
        self.name = name
        M = self.P[:, :3]
        self._M_inv = np.linalg.inv(M)
        # Camera centre: the null vector of P, C = -M^-1 p4.
        self.center = -self._M_inv @ self.P[:, 3]
        # Plain-float copies for the per-frame fast paths (the trackers call view_line and
        # triangulate for single points, where numpy's per-call cost dominates).
        self._minv = [tuple(r) for r in self._M_inv.tolist()]
        self._axis = tuple(self.P[2, :3].tolist())
        self._c = tuple(self.center.tolist())
        self._depth = (*self._axis, float(self.P[2, 3]), float(np.linalg.norm(self.P[2, :3])))
        self._fx = float(self.P[0, 0])

    @classmethod
    def look_at(
        cls,
        eye: Sequence[float],
        target: Sequence[float],
        up: Sequence[float],
        focal: float,
        size: tuple[int, int] = (256, 256),
        name: str = "",
    ) -> Camera:
        """Build a camera at ``eye`` looking at ``target``; ``up`` points to the image top."""
        eye = np.asarray(eye, float)
        forward = np.asarray(target, float) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, np.asarray(up, float))
        right /= np.linalg.norm(right)
        down = np.cross(forward, right)  # image rows grow downwards
        R = np.stack([right, down, forward])
        K = np.array([[focal, 0.0, size[0] / 2.0], [0.0, focal, size[1] / 2.0], [0.0, 0.0, 1.0]])
        P = K @ np.hstack([R, (-R @ eye)[:, None]])
        return cls(P, size, name)

    def project(self, points: np.ndarray) -> np.ndarray:
        """Project world points [N,3] (mm) to pixel coordinates [N,2] (u, v)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        h = pts @ self.P[:, :3].T + self.P[:, 3]
        return h[:, :2] / h[:, 2:3]

    def depth(self, points: np.ndarray) -> np.ndarray:
        """Distance along the optical axis of world points [N,3] (positive in front)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        h = pts @ self.P[:, :3].T + self.P[:, 3]
        scale = np.linalg.norm(self.P[2, :3])
        return h[:, 2] / scale

    def view_line(self, uv: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
        """Back-project pixel ``uv``: (origin = camera centre, unit direction) in world mm."""
        return np.array(self._c), np.array(self._ray(float(uv[0]), float(uv[1])))

    def _ray(self, u: float, v: float) -> tuple[float, float, float]:
        """Unit direction of the view line of pixel (u, v), pointing to the front."""
        (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = self._minv
        x, y, z = a0 * u + a1 * v + a2, b0 * u + b1 * v + b2, c0 * u + c1 * v + c2
        k0, k1, k2 = self._axis
        n = math.sqrt(x * x + y * y + z * z)
        if x * k0 + y * k1 + z * k2 < 0:  # point the ray to the front of the camera
            n = -n
        return x / n, y / n, z / n

    def point_on_plane(self, uv: Sequence[float], axis: int, value: float) -> np.ndarray:
        """Intersect the view line of ``uv`` with the plane {x[axis] = value} (0=x, 1=y, 2=z)."""
        return np.array(self.plane_point(uv, axis, value))

    def plane_point(self, uv: Sequence[float], axis: int, value: float
                    ) -> tuple[float, float, float]:
        """``point_on_plane`` as a tuple of floats (for per-frame trackers)."""
        d = self._ray(float(uv[0]), float(uv[1]))
        if abs(d[axis]) < 1e-9:
            raise ValueError("view line is parallel to the plane")
        o = self._c
        k = (value - o[axis]) / d[axis]
        return o[0] + d[0] * k, o[1] + d[1] * k, o[2] + d[2] * k

    def point_on_plane_z(self, uv: Sequence[float], z: float) -> np.ndarray:
        """Intersect the view line of ``uv`` with the horizontal plane at height ``z``."""
        return self.point_on_plane(uv, 2, z)

    def mm_to_px(self, point: Sequence[float]) -> float:
        """Pixels per millimetre for a small length near ``point`` (perspective scale)."""
        k0, k1, k2, k3, norm = self._depth
        x, y, z = (float(v) for v in point)
        return self._fx / ((k0 * x + k1 * y + k2 * z + k3) / norm)

    def box_region(
        self, lo: Sequence[float], hi: Sequence[float], margin: int = 0
    ) -> tuple[int, int, int, int]:
        """Bounding pixel rectangle (x0, y0, x1, y1), clipped, of the 3-D box [lo, hi]; a box
        outside the image gives a one-pixel rectangle on its nearest edge, never an
        inverted one (a region the robot's watch searched beside the table: round 15)."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        corners = np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1])
                            for c in (lo[2], hi[2])])
        uv = self.project(corners)
        x0, y0 = np.floor(uv.min(axis=0)).astype(int) - margin
        x1, y1 = np.ceil(uv.max(axis=0)).astype(int) + 1 + margin
        w, h = self.size
        x0, y0 = min(max(0, x0), w - 1), min(max(0, y0), h - 1)
        return x0, y0, max(min(w, x1), x0 + 1), max(min(h, y1), y0 + 1)


def triangulate(cam_a: Camera, uv_a: Sequence[float], cam_b: Camera, uv_b: Sequence[float]
                ) -> np.ndarray:
    """Least-squares crossing point of the two view lines (Sec. III-A, the SFD)."""
    # For two lines the point minimising the summed squared distances is the midpoint of
    # their common perpendicular (closed form; the 3x3 normal equations give the same).
    o, p = cam_a._c, cam_b._c
    d = cam_a._ray(float(uv_a[0]), float(uv_a[1]))
    e = cam_b._ray(float(uv_b[0]), float(uv_b[1]))
    w = (o[0] - p[0], o[1] - p[1], o[2] - p[2])
    b = d[0] * e[0] + d[1] * e[1] + d[2] * e[2]
    dw = d[0] * w[0] + d[1] * w[1] + d[2] * w[2]
    ew = e[0] * w[0] + e[1] * w[1] + e[2] * w[2]
    den = 1.0 - b * b
    if den < 1e-12:  # (nearly) parallel lines: no single crossing
        raise np.linalg.LinAlgError("view lines are parallel")
    s, t = (b * ew - dw) / den, (ew - b * dw) / den
    return np.array([(o[0] + s * d[0] + p[0] + t * e[0]) / 2.0,
                     (o[1] + s * d[1] + p[1] + t * e[1]) / 2.0,
                     (o[2] + s * d[2] + p[2] + t * e[2]) / 2.0])


def _fit_focal(eye, target, up, size, margin=6.0) -> float:
    """Largest focal length (px) whose view keeps the whole workspace inside the image."""
    unit = Camera.look_at(eye, target, up, 1.0, size)
    corners = np.array([[x, y, z] for x in (WORKSPACE_LO[0], WORKSPACE_HI[0])
                        for y in (WORKSPACE_LO[1], WORKSPACE_HI[1])
                        for z in (WORKSPACE_LO[2], WORKSPACE_HI[2])])
    offsets = np.abs(unit.project(corners) - np.array(size) / 2.0).max(axis=0)
    half = np.array(size) / 2.0 - margin
    return float((half / offsets).min())


def default_cameras(size: int = 256) -> dict[str, Camera]:
    """The top (looking down) and elevated side camera pair that sees the whole workspace."""
    sz = (size, size)
    centre = (WORKSPACE_LO + WORKSPACE_HI) / 2.0
    table_centre = np.array([centre[0], centre[1], 60.0])
    # Top: straight above the table, +y at the image top, +x to the right.
    top_eye, top_up = (0.0, 200.0, 1400.0), (0.0, 1.0, 0.0)
    # Side: in front of the table (y < 0), raised about 20 degrees so that top faces of
    # stacked blocks show as separate bands (the paper's stereo pair looked down, Sec. II-B).
    side_eye, side_up = (0.0, -1150.0, 520.0), (0.0, 0.0, 1.0)
    top = Camera.look_at(top_eye, (0.0, 200.0, 0.0), top_up,
                         _fit_focal(top_eye, (0.0, 200.0, 0.0), top_up, sz), sz, "top")
    side = Camera.look_at(side_eye, table_centre, side_up,
                          _fit_focal(side_eye, table_centre, side_up, sz), sz, "side")
    return {"top": top, "side": side}


def back_camera(size: int = 512) -> Camera:
    """The execution workspace's third view (the paper watched execution with a camera pair
    of its own): from behind the table's far right corner, raised like the side camera, so
    that a block hidden from the top and the side (a table's back leg under its top, a
    pyramid's middle cube behind the front one) shows from another direction. Its images
    are only asked whether a hidden block's spot is empty (``objects_back.vacant``)."""
    sz = (size, size)
    centre = (WORKSPACE_LO + WORKSPACE_HI) / 2.0
    target = np.array([centre[0], centre[1], 60.0])
    eye, up = (900.0, 200.0 + 900.0, 520.0), (0.0, 0.0, 1.0)
    return Camera.look_at(eye, target, up, _fit_focal(eye, target, up, sz), sz, "back")
