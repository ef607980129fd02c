"""What the current frame shows where the environment model has (or expects) blocks.

The change-detector asks these of the image, through its own windows: is a block
plainly where a box says (``seen_at``), is a picked target still in place
(``still_there``), which block faces from above no known object explains
(``unknown_top``), does the palm still hide a spot from above (``palm_over``).
Each reads only the frame's pixels, through the camera models; the boxes come from
the environment model (docs/seeing.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.model.geometry import footprints_meet
from lbw_engine.see.detectors import ActView
from perception.vision.envnodes.hand import Sight, box
from perception.vision.envnodes.placement import KNOWN_MM, boxes_but, known_boxes, targets_of
from perception.vision.vfd.base import (
    BLOCK_MIN,
    DARK_MAX,
    HAND_BAND,
    Region3D,
    band,
    centroid,
    region_mask,
    regions_mask,
    silhouette,
    visible_outline,
)
from perception.vision.vfd.change import ChangeDetector, Snapshot
from perception.vision.vfd.objects_rings import FRONT_BAND

# A view sees a picked target plainly if other objects' and the hand's images cover at most
# this share of its outline there; it then still sees the target where it was if this share
# of its outline is block-bright in both snapshots (the holder window cannot overrule that).
PLAIN_VIEW, KEPT = 0.2, 0.5
# A block of a picked target's stack has left with the hand when a view sees at least KEPT
# of its outline clear of the hand and of other objects, and at most GONE of that lit.
GONE = 0.1
AWAY_MM = 20.0  # a hand this far beside a block's footprint holds nothing standing there
FACE_PX = 3  # a front face showing fewer pixels than this tells nothing


class Sightings:
    """Questions about the current frame, asked through a change-detector's windows."""

    def __init__(self, sight: Sight, detector: ChangeDetector) -> None:
        """Sightings through ``sight``'s cameras and frame, in ``detector``'s windows."""
        self.sight, self.detector = sight, detector

    def palm_over(self, spot: Region3D) -> bool:
        """Whether the hand covers most of ``spot``'s outline in the top view now."""
        self.detector.attention(spot)
        (window,) = self.detector.windows["top"]
        img = window.read(self.sight.frame.view("top"))
        outline = region_mask(self.sight.cameras["top"], spot, window)
        return bool(outline.any()) and \
            (outline & band(img, *HAND_BAND)).sum() >= KEPT * outline.sum()

    def seen_at(self, region: Region3D, own: set[str], env: EnvModel,
                creases: bool = False, face_px: int = FACE_PX, top: bool = False
                ) -> bool | None:
        """Whether a block fills ``region`` in the current frame: True if the side view
        sees it plainly with its outline bright, False if a view that sees it plainly
        shows it empty (and none bright), None if no view tells. Objects other than
        ``own`` and the held ones hide what they cover; a front face showing fewer than
        ``face_px`` pixels tells nothing (``_front_on_support``). With ``top`` (the hand
        is away from the region, so nothing it lifted hangs over it) the top view may
        say True as well."""
        self.detector.attention(region)
        shot = self.detector.take(self.sight.frame)
        others = boxes_but(env, own | set(env.held()))
        verdicts = {self._front_on_support(region, others, shot, face_px)} - {None}
        for view, (window,) in self.detector.windows.items():
            cam, img = self.sight.cameras[view], shot.pixels[view]
            part = Region3D((*region.lo[:2], region.hi[2] - 1.0), region.hi) \
                if top and view == "top" else region
            outline, clear = visible_outline(cam, part, window, img, others)
            if not outline.any() or clear.sum() < KEPT * outline.sum():
                continue
            # kept: block faces; gone: not even a crease or the arm's gray is left. The top
            # view cannot say kept: a stack lifted straight up still covers its footprint.
            # With ``creases``, a block's crease lines count, and a face pixel or two will
            # do: they are most of a 10 mm cube's image (helper round 9, w83: 2 face
            # pixels of 14 in view).
            bright = float((clear & (img >= BLOCK_MIN)).sum()) / float(clear.sum())
            lit = float((clear & (img > DARK_MAX)).sum()) / float(clear.sum())
            if creases:
                bright = float((clear & silhouette(img)).sum()) / float(clear.sum()) \
                    if (clear & (img >= BLOCK_MIN)).any() else 0.0
            # From above, with the hand away (``top``), whatever is lit in a top face's
            # outline that no other object explains is the block: its top face, or the
            # darker sides the camera sees beside it (a 19 mm pillar 115 mm tall: 30 of 64
            # pixels bright, 26 side-gray, 8 dark)
            kept = bright >= KEPT if view == "side" else top and lit >= KEPT
            verdicts.add(True if kept else False if lit <= GONE else None)
        return True if True in verdicts else False if False in verdicts else None

    def _front_on_support(self, region: Region3D, others: list[Region3D],
                          shot: Snapshot, face_px: int = FACE_PX) -> bool | None:
        """A block standing on others, seen from the side by its front face's shade.

        Its supports' outlines cover its whole image in the side view (the camera looks
        down onto their tops behind it), so ``seen_at`` can say nothing from brightness:
        their top faces are as bright as the block. Its front face has its own shade:
        where it would show, clear of the hand and of everything but the supports, a
        block there shows front-face pixels (True), and none shows the supports' tops
        behind (False). A 10 mm cube picked by the robot from a 60 mm block read as a
        NO-OP, and the place after it as nothing (helper round 12, 27)."""
        z0 = float(region.lo[2])
        below = [b for b in others if b.hi[2] <= z0 + 1.0 and footprints_meet(
            b.center, b.size, region.center, region.size, tol=0.0)]
        if z0 < 1.0 or not below:
            return None
        (window,) = self.detector.windows["side"]
        cam, img = self.sight.cameras["side"], shot.pixels["side"]
        face = Region3D(region.lo, (region.hi[0], region.lo[1], region.hi[2]))
        mask = region_mask(cam, face, window) & ~band(img, *HAND_BAND) & \
            ~regions_mask(cam, [b for b in others if b not in below], window)
        if mask.sum() < face_px:
            return None
        shade = float((mask & band(img, *FRONT_BAND)).sum()) / float(mask.sum())
        return True if shade >= KEPT else False if shade <= GONE else None

    def left_standing(self, node: EnvNode, hand: Sequence[float] | None, env: EnvModel
                      ) -> bool:
        """Whether the hand is away from ``node``'s footprint (by more than AWAY_MM: what it
        lifted would hang under it) and the top view shows the block there. A motion judged
        late (deferred) reads the holder window where the hand is then: a pillar touched in
        a 2 x 2 grid, judged 200 mm away with the tops of other pillars behind the hand in
        the window, read as picked (helper round 20, g3003)."""
        if hand is None or node.position is None or node.size is None:
            return False
        if footprints_meet(tuple(hand), node.size, node.position, node.size, -AWAY_MM):
            return False
        return self.seen_at(box(node), {node.name}, env, top=True) is True

    def still_there(self, act: ActView, env: EnvModel, first: Snapshot, last: Snapshot) -> bool:
        """Whether a view that sees the target plainly shows it unmoved in both snapshots.

        With the hand high above a touched block, the holder window between the fingers
        looks down on the block and can read "holding" (more so with tremor); the side view
        then still shows the block in place, with nothing else projecting onto it. A view
        in which another object lies on the target's line of sight (a block behind it, a
        support below it) or the hand covers it proves nothing: a block there looks the same
        whether the target left or not.
        """
        targets = targets_of(act, env)
        others = boxes_but(env, {n.name for n in targets} | set(env.held()))
        for view, (window,) in self.detector.windows.items():
            cam = self.sight.cameras[view]
            a, b = first.pixels[view], last.pixels[view]
            outline = regions_mask(cam, (box(n) for n in targets), window)
            cover = band(a, *HAND_BAND) | band(b, *HAND_BAND) | regions_mask(cam, others, window)
            area = int(outline.sum())
            if area == 0 or (cover & outline).sum() > PLAIN_VIEW * area:
                continue
            if ((a >= BLOCK_MIN) & (b >= BLOCK_MIN) & outline).sum() >= KEPT * area:
                return True
        return False

    def unknown_top(self, last: Snapshot, env: EnvModel, load: tuple[EnvNode, Region3D] | None
                    ) -> tuple[float, np.ndarray | None]:
        """Share of the top view's window showing block faces that no known object (but
        what the hand holds, unless still under it: ``load``, its box under the hand)
        explains, its outline grown by KNOWN_MM, nor the hand; and where they are (on the
        plane at the region's centre height)."""
        (window,) = self.detector.windows["top"]
        img, cam = last.pixels["top"], self.sight.cameras["top"]
        known = known_boxes(env) + ([load[1].grown(KNOWN_MM)] if load else [])
        new = (img >= BLOCK_MIN) & ~band(img, *HAND_BAND) & ~regions_mask(cam, known, window)
        c = centroid(new)
        if c is None:
            return 0.0, None
        uv = (window.x0 + c[0] * window.step, window.y0 + c[1] * window.step)
        return float(new.sum()) / max(1, img.size), \
            np.asarray(cam.point_on_plane_z(uv, float(last.region.center[2])), float)
