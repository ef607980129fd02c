"""Where a block the change-detector saw placed landed, and what it rests on.

The change-detector (change.py) judges that a place happened; this module says
where. From above, once the hand has left, the top view gives x and y; otherwise
the side camera fixes x and height and the hand at the release gives y (the
block was set down centred between the fingers). Then what the block rests on:
the :Near search chose its targets from what lay under the held block, grown by
a margin; set down, the block may plainly meet only some of them, or none
(``placement.beside_target``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lbw_engine.model.env import EnvModel
from lbw_engine.see.detectors import ActView
from perception.vision.envnodes.placement import (
    beside_target,
    boxes_but,
    nearer,
    onto,
    placed_x,
    side_extent_x,
    targets_of,
    unhidden_x,
)


def where_placed(node: Any, act: ActView, env: EnvModel, pos: np.ndarray | None, last: Any,
                 let_go: Any, top: np.ndarray | None) -> tuple[np.ndarray | None, tuple]:
    """The placed block's position and what it rests on, when the :Near search's choice
    does not hold (() when it does). ``node``: the ChangeNode (its hand, cameras, holder
    view and detector); ``pos``: the centre of the change the judge read, if it read the
    one the env model allows; ``top``: where the top view saw the block, if it did."""
    det = node.detector
    released = node.hand.held_box(env, at=let_go, spot=True)
    held = [env.nodes[n] for n in act.special if n in env.nodes]
    size = held[0].size if held else None
    if top is not None:
        pos = top  # x and y from above; nothing better to fit it to
    else:
        rel = let_go.spot
        x, z = (float(pos[0]), float(pos[2])) if pos is not None else (rel[0], rel[2])
        if pos is not None and size is not None:
            side = node.sight.cameras["side"]
            x = side_extent_x(det, side, x, (float(rel[1]), z), size)
            x = unhidden_x(det, side, x, (float(rel[1]), z), size,
                           nearer(float(rel[1]) - float(size[1]) / 2.0, env))
            if released is not None:
                x = placed_x(det, node.sight.cameras, x, float(released[1].center[0]),
                             (float(rel[1]), z), size, last,
                             boxes_but(env, {held[0].name} | set(env.held())))
        pos = np.array([x, rel[1], z])
    if size is None or released is None:
        return pos, ()
    # Hidden from the side camera, hand and all (behind a 150 mm post, helper round 8's
    # v06), the block's height is a guess: it rests on what is highest under it. With
    # only the block hidden (a second row 6 mm behind a first of its height), the hand
    # above it is in plain view, and its height tells the table from the blocks beside,
    # whatever the side view saw change (round 10's v04z: read 25 mm up, on the four
    # around it). Seen from above, the height is the hand's, or unknown.
    view = node.holder.height_view(released, env, det.windows["side"][0])
    if view == "hand" or (top is not None and view == "block"):
        pos = np.array([pos[0], pos[1], float(released[1].center[2])])
    elif top is not None:
        return pos, ()  # no height: the search's choice stands
    moving = {held[0].name, *env.supported_by(held[0].name), *env.held()}
    hidden = view == "none"
    targets = targets_of(act, env)
    sup = beside_target(env, targets, pos[:2] if hidden else pos, size,
                        np.inf if hidden else float(released[1].lo[2]), moving)
    return (pos if sup else onto(targets, pos, size)), sup
