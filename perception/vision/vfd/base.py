"""The generic Visual Feature Detector (Sec. III-A, Table I, Fig. 2).

A VFD is a stereo feature detector (SFD) made of two monocular detectors
(MFDs), one per camera; the SFD projects a 3-D attention region into both views,
owns the windows the MFDs read, and integrates their 2-D features by
triangulation. ENV-nodes talk to a VFD only through the Table I messages:
``attention``, ``srate``, ``start``, ``stop``, ``found``, ``target``, ``reset``,
``free``. Frames are fed in time order with ``update(frame)`` (online, causal).
Detectors never see the world: only frames, camera models and windows.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from perception.vision.camera import Camera, triangulate
from perception.vision.frames import Frame
from perception.vision.vfd.resources import VisionResources, Window

VIEWS = ("top", "side")

# Gray levels of the rendered images (perception.world.render; docs/vision.md). Detectors
# threshold on bands, so these are the only facts about the renderer they rely on.
BLOCK_MIN = 150  # block faces are 170..255
HAND_BAND = (104, 150)  # the hand is drawn at 128; blocks >= 170, arm 80, creases 60
DARK_MAX = 40  # table, background (0) and noise


@dataclass(frozen=True)
class Region3D:
    """An axis-aligned 3-D box in world mm (an attention or snapshot region)."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]

    @classmethod
    def around(cls, center: Sequence[float], size: Sequence[float]) -> Region3D:
        """The box of ``size`` centred at ``center``."""
        c, s = np.asarray(center, float), np.asarray(size, float) / 2.0
        return cls(tuple((c - s).tolist()), tuple((c + s).tolist()))

    @property
    def center(self) -> np.ndarray:
        """Centre of the box."""
        return (np.asarray(self.lo) + np.asarray(self.hi)) / 2.0

    @property
    def size(self) -> np.ndarray:
        """Full extents along x, y, z."""
        return np.asarray(self.hi) - np.asarray(self.lo)

    def shifted(self, dx: float = 0.0, dy: float = 0.0, dz: float = 0.0) -> Region3D:
        """The same box moved by (dx, dy, dz)."""
        d = np.array([dx, dy, dz])
        return Region3D(tuple((np.asarray(self.lo) + d).tolist()),
                        tuple((np.asarray(self.hi) + d).tolist()))

    def grown(self, mm: float) -> Region3D:
        """The same box grown by ``mm`` on every side."""
        return Region3D(tuple((np.asarray(self.lo) - mm).tolist()),
                        tuple((np.asarray(self.hi) + mm).tolist()))


def region_mask(cam: Camera, region: Region3D, window: Window) -> np.ndarray:
    """Boolean mask of the window's pixels that lie inside the region's projected outline."""
    lo, hi = region.lo, region.hi
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    uv = cam.project(corners) - (window.x0, window.y0)
    hull = cv2.convexHull(np.rint(uv * 16).astype(np.int32))
    mask = np.zeros((window.y1 - window.y0, window.x1 - window.x0), np.uint8)
    cv2.fillConvexPoly(mask, hull, 1, cv2.LINE_8, 4)
    return mask[::window.step, ::window.step] > 0


def regions_mask(cam: Camera, regions: Iterable[Region3D], window: Window) -> np.ndarray:
    """Boolean mask of the window's pixels inside any of the regions' projected outlines."""
    mask = np.zeros((len(range(window.y0, window.y1, window.step)),
                     len(range(window.x0, window.x1, window.step))), bool)
    for region in regions:
        mask |= region_mask(cam, region, window)
    return mask


def visible_outline(cam: Camera, region: Region3D, window: Window, img: np.ndarray,
                    others: Iterable[Region3D]) -> tuple[np.ndarray, np.ndarray]:
    """The region's projected outline in the window, and the part of it where the region
    itself can be seen: clear of the hand and of the ``others`` boxes' outlines (what
    shows there may be theirs)."""
    outline = region_mask(cam, region, window)
    return outline, outline & ~band(img, *HAND_BAND) & ~regions_mask(cam, others, window)


def band(img: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Boolean mask of pixels with lo <= gray <= hi."""
    return (img >= lo) & (img <= hi)


def silhouette(img: np.ndarray) -> np.ndarray:
    """Boolean mask of block pixels: not dark and not the hand's gray, so the crease lines on
    a block's outline count too (they are a third of a 10 mm cube's image)."""
    return (img > DARK_MAX) & ((img < HAND_BAND[0]) | (img > HAND_BAND[1]))


def centroid(mask: np.ndarray) -> tuple[float, float, int] | None:
    """Centre of mass (x, y) and count of a boolean mask, None when empty (GGE feature)."""
    ys, xs = np.nonzero(mask)
    if len(xs) == 0:
        return None
    return float(xs.mean()), float(ys.mean()), len(xs)


class VFD:
    """Generic SFD: Table I interface, windows from the resource manager, stereo integration."""

    def __init__(self, cameras: Mapping[str, Camera], resources: VisionResources) -> None:
        """Share the camera models and the resource manager (Fig. 2)."""
        self.cameras = dict(cameras)
        self.resources = resources
        self.windows: dict[str, list[Window]] = {v: [] for v in VIEWS}
        self.region: Region3D | None = None
        self.rate = 1  # process every ``rate``-th frame
        self.running = False
        self._found = False
        self._target: np.ndarray | None = None

    # -- Table I -------------------------------------------------------------------
    def attention(self, region: Region3D) -> None:
        """Watch ``region``: project it into both views and put one window on each."""
        self.region = region
        for view in VIEWS:
            rect = self.cameras[view].box_region(region.lo, region.hi, margin=1)
            if not self.windows[view]:
                self.windows[view].append(self.resources.allocate(view, rect))
            else:
                self.windows[view][0].set_rect(rect)

    def srate(self, every: int) -> None:
        """Set the sampling rate: process one frame in ``every``."""
        self.rate = max(1, int(every))

    def start(self) -> None:
        """Start detecting on the next frames."""
        self.running = True

    def stop(self) -> None:
        """Stop detecting (state is kept)."""
        self.running = False

    def found(self) -> bool:
        """Whether the feature was found since the last query (clears the flag)."""
        f, self._found = self._found, False
        return f

    def target(self) -> np.ndarray | None:
        """3-D position (mm) of the last detected target, or None."""
        return None if self._target is None else self._target.copy()

    def reset(self) -> None:
        """Clear the internal state (keeps windows and attention)."""
        self._found = False
        self._target = None

    def free(self) -> None:
        """Release every window back to the resource manager."""
        for wins in self.windows.values():
            for w in wins:
                self.resources.free(w)
            wins.clear()
        self.running = False

    # -- per frame -----------------------------------------------------------------
    def update(self, frame: Frame) -> None:
        """Feed the next frame (in time order); processes it when running and due."""
        if self.running and frame.index % self.rate == 0:
            self.process(frame)

    def process(self, frame: Frame) -> None:
        """Extract the feature from ``frame`` (subclasses)."""
        raise NotImplementedError

    # -- stereo integration --------------------------------------------------------------
    def triangulate(self, uv_top: Sequence[float], uv_side: Sequence[float]) -> np.ndarray:
        """Least-squares crossing of the two view lines (the SFD's stereo step)."""
        return triangulate(self.cameras["top"], uv_top, self.cameras["side"], uv_side)
