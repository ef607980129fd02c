"""Change-detector: snapshot subtraction in a target region (Sec. III-D1).

``attention(region)`` puts a window on the region in each view; ``snapshot(frame)``
keeps the window pixels at the start of a LocalMotion, ``compare(frame)`` takes
the final snapshot and classifies the difference by area: an object appeared,
disappeared, or nothing changed. Pixels of the hand's gray band in either
snapshot are masked (the hand may still be in the region at the end). The
centre of the changed area is triangulated (or, if only the side view changed,
taken on the side view line at the region's depth).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from perception.vision.camera import Camera
from perception.vision.frames import Frame
from perception.vision.vfd.base import (
    BLOCK_MIN,
    DARK_MAX,
    HAND_BAND,
    VFD,
    VIEWS,
    Region3D,
    band,
    centroid,
    region_mask,
    regions_mask,
)
from perception.vision.vfd.resources import VisionResources

APPEARED, DISAPPEARED, NO_CHANGE = "appeared", "vanished", "nochange"  # Sec. III-D1
AREA_THRESHOLD = 0.12  # changed fraction of the region's image area that counts as a change
# A view whose changed area was partly behind the hand in one snapshot (block pixels in the
# other one) sees only the uncovered part, and its centre is pulled off the object's; it is
# left out of the position when more than this share is hidden and another view is clear.
HIDDEN_SHARE = 0.25
EXTENT_PX = 2  # an image column is part of a change's extent with this many changed pixels
# A pixel changed shade when its gray moved this much: a block's faces differ by ~85 gray
# levels (renderer), two frames at 4x pixel noise (std 8) by ~11 (std of the difference).
GRAY_STEP = 48
REVEALED_SHARE = 1 / 3  # of a carried block's side outline, hidden, then shown: let go
_SPECK = np.ones((2, 2), np.uint8)


@dataclass(frozen=True)
class Snapshot:
    """The pixels of a region's windows at one moment (opaque to ENV-nodes)."""

    t: float
    region: Region3D
    rects: dict[str, tuple[int, int, int, int]]
    pixels: dict[str, np.ndarray]
    # Window pixels a carried block covers in this snapshot: when it is the first one,
    # they show the load on its way down, and their change counts as nothing gone.
    load: dict[str, np.ndarray] | None = None


class ChangeDetector(VFD):
    """Qualitative change between two snapshots of a region: appeared/disappeared/nochange."""

    def __init__(self, cameras: Mapping[str, Camera], resources: VisionResources,
                 area_threshold: float = AREA_THRESHOLD) -> None:
        """A detector with no region yet (call ``attention``)."""
        super().__init__(cameras, resources)
        self.area_threshold = area_threshold
        # The least net fraction read as a vanished object, when it differs from the
        # appeared one (``area_threshold``); None: the same.
        self.vanish_threshold: float | None = None
        self._first: Snapshot | None = None
        self.result: str | None = None
        self.changed_fraction: dict[str, float] = {}
        # per view, the image columns (first, last) where the last judge's change is solid,
        # and whether that change was pixels appearing (else vanishing)
        self.extent: dict[str, tuple[int, int]] = {}
        self.appeared: dict[str, bool] = {}
        self.centres: dict[str, tuple[float, float]] = {}  # ... and its centre (u, v) px

    def take(self, frame: Frame) -> Snapshot:
        """A snapshot of the current region's windows on ``frame``."""
        if self.region is None:
            raise RuntimeError("change-detector: take() before attention()")
        rects = {v: (w.x0, w.y0, w.x1, w.y1) for v, (w,) in self.windows.items()}
        return Snapshot(frame.t, self.region, rects,
                        {v: self.windows[v][0].read(frame.view(v)).copy() for v in VIEWS})

    def snapshot(self, frame: Frame) -> Snapshot:
        """Initial snapshot of the region (start of the LocalMotion); also returned."""
        self._first = self.take(frame)
        self.result = None
        return self._first

    def process(self, frame: Frame) -> None:
        """Per-frame update: nothing to do between the two snapshots."""

    def compare(self, frame: Frame) -> str:
        """Final snapshot on ``frame``: classify the change against the initial one."""
        if self._first is None:
            raise RuntimeError("change-detector: compare() before snapshot()")
        return self.judge(self._first, self.take(frame))

    def judge(self, first: Snapshot, last: Snapshot) -> str:
        """Classify the change between two snapshots of one region and locate its centre."""
        if first.rects != last.rects:
            raise ValueError("change-detector: the two snapshots cover different regions")
        votes, centres, hidden = {}, {}, {}
        for v in VIEWS:
            x0, y0 = first.rects[v][:2]
            a, b = first.pixels[v], last.pixels[v]
            hand_a, hand_b = band(a, *HAND_BAND), band(b, *HAND_BAND)
            hand = hand_a | hand_b
            obj_a, obj_b = (a > DARK_MAX) & ~hand, (b > DARK_MAX) & ~hand
            appeared, gone = obj_b & ~obj_a, obj_a & ~obj_b
            if first.load is not None:
                gone &= ~first.load[v]
            if last.load is not None:  # the load still in the hand at the end: not set down
                appeared &= ~last.load[v]
            net = (int(appeared.sum()) - int(gone.sum())) / max(1, a.size)
            votes[v] = net
            self.changed_fraction[v] = abs(net)
            changed = appeared if net > 0 else gone
            self.appeared[v] = net > 0
            # Object pixels of the later (appeared) or earlier (gone) snapshot that the hand
            # covered in the other one: the change there cannot be seen.
            covered = hand_a & ~hand_b & (b > DARK_MAX) if net > 0 else \
                hand_b & ~hand_a & (a > DARK_MAX)
            n_changed, n_covered = int(changed.sum()), int(covered.sum())
            hidden[v] = n_covered > HIDDEN_SHARE * max(1, n_changed + n_covered)
            c = centroid(changed)
            if c is not None:
                centres[v] = (x0 + c[0], y0 + c[1])
            cols = np.nonzero(changed.sum(axis=0) >= EXTENT_PX)[0]
            if len(cols):
                self.extent[v] = (x0 + int(cols[0]), x0 + int(cols[-1]))
            else:
                self.extent.pop(v, None)
        self.centres = centres
        passing = [v for v in VIEWS if abs(votes[v]) >= self.need(votes[v])]
        if not passing:
            self.result, self._target = NO_CHANGE, None
            return self.result
        view = max(passing, key=lambda v: abs(votes[v]))
        self.result = APPEARED if votes[view] > 0 else DISAPPEARED
        same = [v for v in VIEWS if abs(votes[v]) >= self.need(votes[v]) / 2
                and np.sign(votes[v]) == np.sign(votes[view]) and v in centres]
        region = first.region
        if len(same) == 2 and hidden[same[0]] != hidden[same[1]]:
            same = [v for v in same if not hidden[v]]  # the clear view alone
        elif len(same) < 2:
            same = ["side" if "side" in centres else "top"]
        if len(same) == 2:
            self._target = self.triangulate(centres["top"], centres["side"])
        elif same == ["side"]:
            self._target = self.cameras["side"].point_on_plane(
                centres["side"], 1, float(region.center[1]))
        else:
            self._target = self.cameras["top"].point_on_plane_z(
                centres["top"], float(region.center[2]))
        self._found = True
        return self.result


    def need(self, vote: float) -> float:
        """The least net changed fraction that reads as a change of ``vote``'s sign."""
        if vote < 0 and self.vanish_threshold is not None:
            return self.vanish_threshold
        return self.area_threshold


def shade_change(first: Snapshot, last: Snapshot) -> float:
    """The largest share, over the views, of a region's window whose block pixels changed
    shade between two snapshots (hand pixels and lone speckles left out).

    A block set down onto or in front of others, whose faces were already bright in the
    window, changes their shades more than the count of bright pixels: a slab laid across
    a row seen from the side covers the row's top faces with its own front face.
    """
    import cv2

    out = 0.0
    for v in VIEWS:
        a, b = first.pixels[v].astype(np.int16), last.pixels[v].astype(np.int16)
        hand = band(first.pixels[v], *HAND_BAND) | band(last.pixels[v], *HAND_BAND)
        changed = (np.abs(b - a) > GRAY_STEP) & ((a > DARK_MAX) | (b > DARK_MAX)) & ~hand
        changed = cv2.morphologyEx(changed.astype(np.uint8), cv2.MORPH_OPEN, _SPECK)
        out = max(out, float(changed.sum()) / max(1, changed.size))
    return out


def revealed(cam: Camera, window, first: Snapshot, last: Snapshot, size, known) -> bool:
    """Whether the side view shows a carried block let go where the hand hid it: in the
    landing box (``first.region``), block faces that no ``known`` box explains show with
    no hand in ``last`` where the hand was in ``first``, over a third of the side outline
    of a block of ``size``.

    Jaws closed along y put a finger between the side camera and the block, and the palm
    hides it from above: a robot's 15 mm cube set down 6 mm beside another was neither
    seen between the fingers nor seen to appear, since pixels the hand covered in
    either snapshot count for nothing (helper round 7, u24: the monitor then redid the
    place). Still held, the block would stay behind the finger."""
    a, b = first.pixels["side"], last.pixels["side"]
    shown = region_mask(cam, first.region, window) & band(a, *HAND_BAND) & \
        (b >= BLOCK_MIN) & ~band(b, *HAND_BAND) & ~regions_mask(cam, known, window)
    own = int(region_mask(cam, Region3D.around(first.region.center, size), window).sum())
    return own > 0 and int(shown.sum()) >= REVEALED_SHARE * own
