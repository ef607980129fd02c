"""What the holder window between the fingers shows (Sec. III-C3), objects in view or not.

The side camera sees, between the open fingers, whatever stands behind or in front
of the hand at that height, as well as the hand's load. ``HolderView`` reads the
window against the environment model: which of its pixels other known objects
explain, how much of a held block those nearer the camera hide, and whether the
window can say anything at all (docs/seeing.md, "holder window").
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.see.detectors import ActView
from perception.vision.envnodes.hand import HandState
from perception.vision.envnodes.placement import boxes_but, nearer
from perception.vision.vfd.base import BLOCK_MIN, Region3D, region_mask, regions_mask

# The holder window's block pixels are counted only where no other known object's image
# falls; when less than this share of the window is left, the whole window counts.
HOLDER_CLEAR = 0.2
HIDDEN = 0.5  # a released block shows less of its side outline: its height is unseen


class HolderView:
    """The tracked hand's holder window, read against the environment model."""

    def __init__(self, hand: HandState) -> None:
        """A view of ``hand``'s holder window through its sight's side camera."""
        self.hand = hand

    def unexplained(self, act: ActView, env: EnvModel) -> float:
        """Block fraction of the holder window that no other known object explains.

        Between open fingers the side camera also sees whatever stands behind or in front
        of the hand at that height: a robot lifting straight up from a block it set down
        behind a neighbour has a third block far behind in its holder window (fault bench
        9007, 0.42 block pixels, read as still holding). Pixels where another object of
        the environment model projects are left out; the motion's own objects (its
        target, what the hand carries) are not, since they are what the window asks about.
        Only "is the hand empty?" asks this: a held block in front of a known object
        would lose its pixels there ("is it holding?" is ``in_hand``).
        """
        return self._share(self.clear(act, env))

    def clear(self, act: ActView, env: EnvModel) -> np.ndarray | None:
        """The window's pixels where no known object but the motion's own projects
        (``unexplained``); None when they are fewer than HOLDER_CLEAR of it: the side
        view then sees those objects, not the hand's load."""
        own = set(env.held()) | {n.name for n in env.get(act.target)}
        return self._clear_of(boxes_but(env, own))

    def in_hand(self, load: Region3D | None, env: EnvModel) -> float:
        """Block fraction of the window, leaving out where known objects nearer the side
        camera than ``load`` (a block in the hand) project: those hide the hand and show
        themselves (an empty hand rising behind a 120 mm post read as holding the cube it
        had touched, helper round 8, v59). Objects behind it stay in: a held block
        covers them."""
        if load is None:
            return self.hand.tracker.holding_evidence
        return self._share(self._clear_of(nearer(float(load.lo[1]), env)))

    def _clear_of(self, boxes: list[Region3D]) -> np.ndarray | None:
        """The window's pixels where none of ``boxes`` projects; None without a frame, or
        when they are fewer than HOLDER_CLEAR of the window."""
        if self.hand.sight.frame is None:
            return None
        window = self.hand.tracker.holder.window
        clear = ~regions_mask(self.hand.sight.cameras["side"], boxes, window)
        return None if clear.sum() < HOLDER_CLEAR * clear.size else clear

    def _share(self, clear: np.ndarray | None) -> float:
        """Block fraction of the window's ``clear`` pixels; with none, the whole window's."""
        if clear is None:
            return self.hand.tracker.holding_evidence
        sub = self.hand.tracker.holder.window.read(self.hand.sight.frame.view("side"))
        return float(((sub >= BLOCK_MIN) & clear).sum()) / float(clear.sum())

    def visible_fill(self, held: tuple[EnvNode, Region3D], env: EnvModel) -> float:
        """Share of the window a held block's side image can fill (``HandState.held_fill``),
        less what known objects nearer the side camera hide of it: a cube carried down
        behind a 150 mm post (helper round 8, v06) showed 0.28 of the window, and was read
        as still held after it was set down."""
        return self.shown(held, env, self.hand.tracker.holder.window) * \
            self.hand.held_fill(held[1])

    def height_view(self, released: tuple[EnvNode, Region3D], env: EnvModel, window: Any
                    ) -> str:
        """What the side view shows of a block let go: "block" (its outline, HIDDEN or
        more of it), "hand" (only the space above it, where the hand rose from: the
        tracked hand's height holds), or "none" (neither: its height is unseen)."""
        if self.shown(released, env, window) >= HIDDEN:
            return "block"
        above = released[1].shifted(dz=float(released[1].size[2]))
        return "hand" if self.shown((released[0], above), env, window) >= HIDDEN else "none"

    def shown(self, held: tuple[EnvNode, Region3D], env: EnvModel, window: Any) -> float:
        """Share of a held block's side outline in ``window`` that no known object nearer
        the side camera hides."""
        cam = self.hand.sight.cameras["side"]
        outline = region_mask(cam, held[1], window)
        if not outline.any():
            return 0.0
        front = nearer(float(held[1].lo[1]), env, {held[0].name})
        return float((outline & ~regions_mask(cam, front, window)).sum() / outline.sum())
