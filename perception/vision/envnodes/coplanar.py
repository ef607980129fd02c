"""The coplanar-detector ENV-node: CoplDet, did a moved block's side face line up (Fig. 5)?

A FineMotion's snapshots list the (neighbour, face) pairs whose vertical faces
are coplanar with the moved block's, judged from edge junctions in the image
(perception/vision/vfd/coplanar.py); the comparison answers the temporal
difference of the truth value (Table V caption): 1 when a coplanar pair
appeared as the block slid (ALIGN; rules ``align-slide``), -1 when one was lost, 0
otherwise, and names the neighbours.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lbw_engine.model.env import EnvModel
from lbw_engine.see.detectors import ActView, Detection
from perception.vision.envnodes.base import EnvNodeBase
from perception.vision.envnodes.hand import box
from perception.vision.envnodes.placement import settled
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.coplanar import CoplanarDetector

# two blocks closer than this side by side are in contact (for CoplDet): each box is a few
# mm off, the held one from the hand at the release, the other from its own place (a cube
# slid into line with a 120 mm tower's north face measured 7 mm from it: round 17, u221)
CONTACT_MM = 9.0
# ... or overlapping by up to this much: the held block's box comes from the hand at the
# release, which tremor and the grip estimate put 5-8 mm into a neighbour it touches
OVERLAP_MM = 12.0
LEVEL_MM, LEVEL_SHARE = 10.0, 0.5  # bottoms of side-by-side blocks: within this, this share
MODEL_TOLERANCE_MM = 10.0  # a hidden face pair: coplanar by the measured boxes within this
# ALIGN is a slide (Sec. V-B5): a block let go within rules/constants.yaml `align-slide`
# (x, y) of where it came down was put in line, not slid into it. The first snapshot is
# taken with the block still in the air, where no face pair is judged, so every block set
# down flush with a neighbour read as an ALIGN (a user's row of cubes 5 mm apart along y).
# The palm seen from above must have moved by this share of that too: the side view's
# fingers can be hidden behind a block in front, the top view's palm is not.
TOP_SHARE = 0.5
# Where a block in front stands HIDE_MM above the held one, the fingers are out of the side
# camera's sight, and the held box goes where the top view's palm puts it, if that lies
# TOP_TRUST_MM from the tracked point beyond how the two differed high in the carry (a
# 30 mm cube slid 13 mm along a 120 mm tower in front of it measured 39 mm: round 17,
# u88). Only there: in the open they differ by up to 7 mm as the hand turns, and a 20 mm
# tile set down 2 mm behind another read as slid (u48).
HIDE_MM, TOP_TRUST_MM = 20.0, 6.0




class CoplanarNode(EnvNodeBase):
    """CoplDet: are the moved block's faces coplanar with a neighbour's (Fig. 5, ALIGN)?"""

    name = "coplanar-detector"
    answers = (1, 0, -1)  # difference of truth values, end minus start (Table V caption)

    def __init__(self, *args: Any) -> None:
        """A coplanar-detector on the shared windows."""
        super().__init__(*args)
        self.detector = CoplanarDetector(self.sight.cameras, self.sight.resources)

    def status(self, act: ActView, env: EnvModel) -> dict[str, Any]:
        """(neighbour, face) pairs whose face is coplanar with the moved block's, and whether
        some face was hidden (then judged from the measured boxes instead of the image)."""
        self.hand.observe(env)
        # where the hand let go of it (or holds it now): it stays there (Sec. V-B5)
        let_go = self.hand.let_go(act.since)
        held = self.hand.held_box(env, at=let_go)
        if held is not None and let_go is not None:
            held = held[0], self._from_above(held[0].name, held[1], let_go, env)
        if held is None or self.sight.frame is None:
            return {"pairs": set(), "hidden": False, "at": None, "offsets": {}, "modelled": set(),
                    "top": None}
        top = (let_go or self.hand.at(self.sight.t)).top
        node, a = held[0], settled(held[1], act, env)
        out, hidden, offsets, modelled = set(), False, {}, set()
        for other in env.objects():
            if other.name == node.name or other.position is None or other.size is None:
                continue
            b = box(other)
            # side by side at one level: bottoms this close, and never a block's height
            # apart (10 mm cubes stacked exactly read as ALIGNed, helper round 9, w23)
            level = min(LEVEL_MM, LEVEL_SHARE * min(float(a.size[2]), float(b.size[2])))
            for axis, faces in ((1, ("east", "west")), (0, ("north", "south"))):
                across = 1 - axis
                gap = abs(a.center[axis] - b.center[axis]) - (a.size[axis] + b.size[axis]) / 2
                overlap = (a.size[across] + b.size[across]) / 2 - abs(a.center[across]
                                                                      - b.center[across])
                # side by side along this axis (not overlapping along it), faces across it
                if not -OVERLAP_MM <= gap <= CONTACT_MM or overlap <= 0 \
                        or abs(a.lo[2] - b.lo[2]) > level:
                    continue
                for face in faces:
                    offset = offsets[(other.name, face)] = abs(_face(a, face) - _face(b, face))
                    seen = self.detector.check(self.sight.frame, a, b, face)
                    if self.detector.step_mm is None:  # the palm or a finger hides an edge
                        hidden = True
                        seen = offset <= MODEL_TOLERANCE_MM
                        modelled.add((other.name, face))
                    if seen:
                        out.add((other.name, face))
        self.detector.free()
        return {"pairs": out, "hidden": hidden, "at": (float(a.center[0]), float(a.center[1])),
                "offsets": offsets, "modelled": modelled, "top": top}

    def _from_above(self, name: str, held: Region3D, at: Any, env: EnvModel) -> Region3D:
        """The held box ``held`` at sample ``at``, moved (x, y) where the top view's palm
        puts it when a taller block in front hides the fingers (HIDE_MM, TOP_TRUST_MM)."""
        if at.top is None or not _hidden_behind(held, env):
            return held
        d = self.hand.top_offset(name, at.t)
        if d is None:
            return held
        dx, dy = np.asarray(at.top) - d - at.hand[:2]
        return held.shifted(float(dx), float(dy)) if math.hypot(dx, dy) > TOP_TRUST_MM \
            else held

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """Coplanar face pairs now."""
        return self.status(act, env)

    def pending(self, last: Any) -> bool:
        """The end state cannot be judged yet: the hand still hides a face's edge (the engine
        then asks again on later frames, until the hand has cleared it or the parent ends)."""
        return bool(last and last["hidden"])

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """positive: a coplanar pair appeared as the block slid; negative: one was lost;
        else unchanged."""
        start = first.get("at") if first else None
        end = last.get("at") if last else None
        before = first.get("offsets", {}) if first else {}
        after = last.get("offsets", {}) if last else {}
        modelled = first.get("modelled", set()) if first else set()
        first_top = first.get("top") if first else None
        last_top = last.get("top") if last else None
        first = first["pairs"] if first else set()
        last = last["pairs"] if last else set()
        # A pair coplanar at both ends appeared too if, at the start, the fingers hid its
        # faces (the measured boxes then call faces 8 mm apart coplanar, MODEL_TOLERANCE_MM;
        # a user's 8 mm slide) and the slide brought them `align-slide` closer.
        slid = float(self.rules.constants["align-slide"])
        appeared = {p for p in last if p not in first
                    or (p in modelled and _closed(p, before, after, start, end, slid))}
        if start is not None and end is not None and math.dist(start, end) < slid:
            appeared = set()  # put down flush where it came down: not slid into line
        tops = (first_top, last_top)
        if None not in tops and math.dist(*tops) < TOP_SHARE * slid:
            # the top view saw the palm stay where it was: a finger hidden behind a taller
            # block in front put the tracked hand 7 mm off (helper round 12, 14)
            appeared = set()
        sign = 1 if appeared else -1 if first - last else 0
        # the neighbours whose faces became coplanar with the moved block's (ALIGN's `found`)
        found = tuple(sorted({name for name, _ in appeared}))
        return Detection(value=sign, found=found)


def _closed(pair: tuple[str, str], before: dict, after: dict, start, end, slid: float) -> bool:
    """Whether a slide brought a face pair that was judged from the measured boxes at its
    start (the fingers hid the faces) into line: their offset shrank by ``slid``, or the
    block slid ``slid`` itself. The boxes' offsets are a few millimetres off: a 30 x 60
    block slid 7 mm west measured 4.6 mm from flush at the start and 2.2 mm at the end;
    one set down flush on its west face and slid 6 mm north into contact, coplanar at
    both ends (helper round 13, 43, v43g)."""
    if before.get(pair, 0.0) - after.get(pair, 0.0) >= slid:
        return True
    return start is not None and end is not None and math.dist(start, end) >= slid


def _face(region: Region3D, face: str) -> float:
    """World coordinate of a box's named vertical face (north/south: y, east/west: x)."""
    axis = 1 if face in ("north", "south") else 0
    return float(region.hi[axis] if face in ("north", "east") else region.lo[axis])


def _hidden_behind(held: Region3D, env: EnvModel) -> bool:
    """Whether a block stands in front of ``held`` (nearer the side camera, -y), across
    its x, with its top HIDE_MM or more above the held block's: the fingers holding it
    are out of the side camera's sight."""
    for node in env.objects():
        if node.position is None or node.size is None or node.name in env.held():
            continue
        b = box(node)
        if b.hi[1] <= held.lo[1] + 1.0 and b.hi[2] >= held.hi[2] + HIDE_MM and \
                b.lo[0] < held.hi[0] and b.hi[0] > held.lo[0]:
            return True
    return False
