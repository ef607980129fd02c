"""The change-detector ENV-node: SilDiff, what changed in a motion's target region.

At a motion's start and end the change-detector takes snapshots of the region
Fig. 6(3) prescribes (the target block with an empty hand; the place just above
the target, sized like the held object, with a full one) and judges them by
image subtraction and area thresholding (Sec. III-D1): ``appeared``, ``vanished``
or ``nochange``, with the centre of the change. Regions come from the environment
model and the tracked hand; pixels only from the current frame (docs/seeing.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.model.geometry import footprints_meet
from lbw_engine.see.detectors import ActView, Detection
from perception.vision.envnodes.base import EnvNodeBase
from perception.vision.envnodes.hand import box
from perception.vision.envnodes.holder import HolderView
from perception.vision.envnodes.landing import where_placed
from perception.vision.envnodes.placement import (
    boxes_but,
    known_boxes,
    settled,
    targets_of,
)
from perception.vision.envnodes.sightings import Sightings
from perception.vision.vfd.base import (
    DARK_MAX,
    HAND_BAND,
    Region3D,
    band,
    region_mask,
    regions_mask,
)
from perception.vision.vfd.change import (
    APPEARED,
    AREA_THRESHOLD,
    DISAPPEARED,
    NO_CHANGE,
    ChangeDetector,
    Snapshot,
    revealed,
    shade_change,
)

PLACE_MARGIN_MM = 25.0  # snapshot region around a place spot (approach slant, align slide)
PICK_MARGIN_MM = 8.0
HOLDING, EMPTY = 0.6, 0.1  # block fraction of the holder window: an object held / none
# (a grasped block fills it, 0.9-1; after a touch a block below can show in it, ~0.3)
HOLD_SHARE = 0.35  # of the share a held block's image covers: a small block held (held_fill)
# A place's change threshold is never asked of fewer changed pixels than a third of this
MIN_CHANGE_PX = 6  # (noise flips single pixels; a 10 mm cube fully in view changes ~10)
LOAD_MM = 3.0  # the carried block's outline grown by this (tremor, tracking)
VACANT_PX = 20  # front-face pixels that may show a let-go spot empty (to refuse a shade)
BESIDE_MM = 10.0  # a block this close beside a picked target may be the one the hand took

class ChangeNode(EnvNodeBase):
    """SilDiff: change-detector snapshots of a motion's target region (Sec. III-D1)."""

    name = "change-detector"
    answers = (APPEARED, DISAPPEARED, NO_CHANGE)  # the change-detector's own words

    def __init__(self, *args: Any) -> None:
        """A change-detector on the shared windows."""
        super().__init__(*args)
        self.detector = ChangeDetector(self.sight.cameras, self.sight.resources)
        self.holder = HolderView(self.hand)
        self.sights = Sightings(self.sight, self.detector)

    def region(self, act: ActView, env: EnvModel) -> tuple[Region3D, tuple[float, ...]] | None:
        """Snapshot region (Fig. 6(3)) and the expected object box size."""
        targets = [n for n in env.get(act.target) if n.position is not None]
        held = self.hand.held_box(env)
        if held is not None and act.special:
            node, hb = held
            tops = [n.top() for n in targets] or [0.0]
            c = hb.center
            h = float(node.size[2])
            m = PLACE_MARGIN_MM
            return (Region3D.around((c[0], c[1], max(tops) + h / 2.0),
                                    (node.size[0] + 2 * m, node.size[1] + 2 * m, h)),
                    node.size)
        locs = [n for n in targets if n.kind == "Loc" and n.size is not None]
        if not locs:
            return None
        lo = np.min([np.asarray(box(n).lo) for n in locs], axis=0) - PICK_MARGIN_MM
        hi = np.max([np.asarray(box(n).hi) for n in locs], axis=0) + PICK_MARGIN_MM
        lo[2] = max(lo[2], 0.5)
        return Region3D(tuple(lo), tuple(hi)), locs[0].size

    def snapshot(self, act: ActView, env: EnvModel) -> Any:
        """First snapshot: the region and its window pixels; the last one is taken at compare."""
        if self.sight.frame is None:
            return None
        self.hand.observe(env)
        found = self.region(act, env)
        if found is None:
            return None
        (region, size), det = found, self.detector
        held = self.hand.held_box(env) if act.special else None
        fill = self.holder.visible_fill(held, env) if held is not None else None
        blind = self.holder.clear(act, env) is None or self.too_small(act, env, held, fill)
        det.attention(region)
        shot = det.take(self.sight.frame)
        if held is not None:
            shot = self.carrying(shot, held[1])
        return {"size": size, "shot": shot, "hold": self.hand.tracker.holding_evidence,
                "empty": self.holder.unexplained(act, env), "place": held is not None,
                "blind": blind, "fill": fill}

    def too_small(self, act: ActView, env: EnvModel, held: tuple[EnvNode, Region3D] | None,
                  fill: float | None) -> bool:
        """Whether the block the motion moves is too small for the holder window to tell
        held from not (its share of it, times HOLD_SHARE, at most EMPTY), while the palm
        still covers from above where it was let go, or where it stood for a pick: a 12 mm
        cube set down 4 mm in front of another showed the side camera crease lines over
        the other's face (helper round 9, w24); a 10 mm cube picked behind a crate showed
        it nothing (bench 1264, the robot watch). For a pick, also while no view tells
        whether it still stands there: a 10 mm cube lifted from 6 mm behind a 60 mm block
        was still behind it at the motion's end (helper round 11, v53a)."""
        if held is not None:
            spot = self.hand.held_box(env, at=self.hand.let_go(act.since), spot=True)
            spot = settled(spot[1], act, env) if spot is not None else None
        else:
            targets = targets_of(act, env)
            if not targets or self.hand.hand is None:
                return False
            lift = (targets[0], Region3D.around(self.hand.hand, targets[0].size))
            fill, spot = self.holder.visible_fill(lift, env), box(targets[0])
            # ... or one the window does not show held (the robot's near jaw hides it when
            # the jaws close along y), while no view tells whether it still stands there
            # (a cube picked behind a taller tower, the palm over its spot: helper round
            # 15's AI, a right pick watched as a NO-OP and redone)
            if (held_bar(fill) <= EMPTY or self.holder.in_hand(lift[1], env) < held_bar(fill)) \
                    and self.seen(targets[0], env) is None:
                return True
        return spot is not None and fill is not None and held_bar(fill) <= EMPTY \
            and self.sights.palm_over(spot)

    def pending(self, last: Any) -> bool:
        """The end state cannot be judged yet: known objects (a tall block between the
        side camera and the hand) fill the holder window, so the side view cannot tell
        whether the hand still holds a block, and the palm hides the spot from above.
        The engine asks again on later frames, as the hand leaves (helper round 8: a
        cube set down behind a 150 mm post read as still held, v06, v11; one touched
        there as picked, v59)."""
        return bool(last and last.get("blind"))

    def carrying(self, shot: Snapshot, held: Region3D) -> Snapshot:
        """``shot`` with the outline of the block the hand carries in it (grown by LOAD_MM).

        The load hangs in a place's region (a tall block above its spot, a hand coming in
        slanted): the pixels it covers now can only be left by the load itself, never by a
        block that vanished; a block set down behind another shows little and would lose."""
        load = held.grown(LOAD_MM)
        return replace(shot, load={v: region_mask(self.sight.cameras[v], load, w)
                                   for v, (w,) in self.detector.windows.items()})

    def compare(self, first: Any, last: Any, act: ActView, env: EnvModel) -> Detection | None:
        """Appeared / disappeared / no-change, and where (for a place: the release point)."""
        if self.sight.frame is None:
            return None
        if not first:
            # no region to watch: an empty hand came to no block (the search named the
            # table) and left. Nothing it could take or set down was in sight: no change
            # (generated stacked-start 1266 at 4x: the motion had no operation at all)
            return Detection(value=NO_CHANGE) if not act.special else None
        det, shot = self.detector, first["shot"]
        place = bool(first.get("place"))
        load = self.hand.held_box(env) if place else None  # the held block under the hand
        # the load still hangs under the hand: what it covers now is no placed block (a
        # touch with a block in hand, the hand back over the spot at the :Far)
        kept = load is not None and self.sights.seen_at(load[1], {load[0].name}, env) is True
        # ... and where the hand let it go, set on the target, the side view sees a block
        # plainly that no known object explains (a 10 mm cube set on another shows 0.06
        # of the holder window, within an empty hand's noise: helper round 9, w83)
        set_down = self.hand.held_box(env, at=self.hand.let_go(act.since), spot=True) \
            if place and not kept else None
        spot = settled(set_down[1], act, env) if set_down is not None else None
        at_spot = self.sights.seen_at(spot, {set_down[0].name}, env, creases=True) \
            if set_down is not None else None
        landed = at_spot is True
        # ... or plainly sees it empty, where a front face counts only with VACANT_PX pixels
        # or more (a view's own dark reading counts as ever): a 180 mm beam touched
        # to the beam it then went on, and lifted, showed 386 dark face pixels there (bench
        # 1097 at 2x, read as placed from a shade change of 0.112, 0.111 asked); a 10 mm
        # cube set on a plate showed 5, all dark (helper round 15's 54)
        vacant = at_spot is False and self.sights.seen_at(
            spot, {set_down[0].name}, env, creases=True, face_px=VACANT_PX) is False
        det.attention(shot.region)
        det.area_threshold = self.threshold(shot, first["size"], place=place,
                                            others=() if place else self.in_sight(act, env))
        # A place's threshold is what the carried block can still add to the landing box,
        # little when it is already low there (a robot sets a block down slowly); that says
        # nothing about a block vanishing, which takes its whole outline with it.
        det.vanish_threshold = self.threshold(shot, first["size"]) if place else None
        last = det.take(self.sight.frame)
        if kept:
            last = self.carrying(last, load[1])
        result = det.judge(shot, last)
        if result == (DISAPPEARED if act.special else APPEARED):
            # the env model allows neither: an empty hand sets nothing down, a full one
            # picks nothing up. The net change is the hand's load moving in the window
            # (4x tremor: a cube lifted from a pyramid read as appeared, bench 1290);
            # the holder window decides, as when nothing changed.
            result = NO_CHANGE
        # the centre of a change the judge read is where the block went only if it read
        # one the env model allows (a cube set down behind a tower was placed at the
        # centre of what vanished, 32 mm off: helper round 8, v11)
        pos, top = det.target() if det.result == result else None, None
        taken: tuple[str, ...] = ()  # a block beside the target that left with the hand
        if result == NO_CHANGE:
            # The region may be hidden at the end (the palm above it in the top view, a block
            # in front of it in the side view); the holder window between the fingers
            # (Sec. III-C3) then tells whether the object left or joined the hand.
            # Only the way the env model allows: a block can leave the hand only if the motion
            # carried one (its special slot), and join it only if the hand came empty (a block
            # seen between open fingers above a touched one is not a grasp).
            # "Holding" reads the whole window; "empty" leaves out other known objects'
            # pixels, which can only add block pixels to an empty window (``unexplained``).
            before = first["hold"]
            emptied = self.holder.unexplained(act, env) <= EMPTY and not kept
            # a small block held fills only part of the window (HandState.held_fill); one
            # picked hangs about where the hand is (a 10 mm disk lifted off a lintel showed
            # 0.39 of it: helper round 7, u43, where the monitor then undid a set-aside)
            targets = targets_of(act, env)
            lift = None if act.special or not targets or self.hand.hand is None else \
                Region3D.around(self.hand.hand, targets[0].size)
            fill = first.get("fill")
            if fill is None and (load is not None or lift is not None):
                fill = self.hand.held_fill(load[1] if load else lift)
            held = HOLDING if fill is None else held_bar(fill)
            if act.special and before > EMPTY and before >= held and emptied:
                result = APPEARED
            elif act.special and emptied and landed:
                # where it was let go. A block dropped on the way that landed there reads
                # as placed too (fault bench 3000: a plate dropped beside its goal, which
                # the cameras then verify); asking that the holder window saw it held at
                # the start lost a 30 mm cube set on a tower beside a 150 mm post, which
                # showed 0.06 of the window (helper round 10, y10)
                result = APPEARED
            elif act.special and emptied and not vacant and \
                    shade_change(shot, last) >= det.area_threshold:
                # set down onto or in front of blocks already in view; not where a view
                # plainly sees the spot it was let go at empty (``vacant``)
                result = APPEARED
            elif act.special and emptied and \
                    (seen := self.sights.unknown_top(last, env, load))[0] >= det.area_threshold:
                # seen from above once the hand has left: block faces where no known object
                # lies (the palm hid the spot at the first snapshot, a block in front hides
                # it from the side: a 12 mm cube set behind a tower, helper round 4, s09);
                # there, not at the release point (a block dropped on the way lands short)
                result, top = APPEARED, seen[1]
            elif act.special and emptied and revealed(self.sight.cameras["side"],
                                                      det.windows["side"][0], shot, last,
                                                      first["size"], known_boxes(env)):
                result = APPEARED  # the finger that hid it has let it go
            elif (not act.special and first.get("empty", before) <= EMPTY
                  and self.holder.in_hand(lift, env) >= held
                  and not self.sights.still_there(act, env, shot, last)
                  and not self.sights.left_standing(targets[0], self.hand.hand, env)):
                result = DISAPPEARED
            elif (not act.special and first.get("empty", before) <= EMPTY
                  and (taken := self.lifted(act, env, hidden=True))
                  and self.holds(env.nodes[taken[0]], env)):
                # the target stands unmoved, and a block beside it left with the hand: the
                # search named a taller neighbour 8 mm behind the cube the robot took
                # (helper round 10, v06x: a cube set aside in front of a 40 mm one)
                result = DISAPPEARED
            elif (not act.special and first.get("empty", before) <= EMPTY and targets
                  and held <= EMPTY and self.seen(targets[0], env) is False):
                # too small for the holder window to show it held, and a view that sees
                # its place plainly shows it empty (a block the window could show held
                # is not picked for that alone: the robot's push into contact slides
                # one off its place with closed jaws, helper round 10, x27)
                result = DISAPPEARED
        let_go, found = self.hand.let_go(act.since), ()
        if result == APPEARED and let_go is not None:
            pos, found = where_placed(self, act, env, pos, last, let_go, top)
        elif result == APPEARED and top is not None:
            pos = top  # x and y from above; nothing better to fit it to
        up = {}  # where the picked block hangs now (actions.json's PICK final state)
        if result == DISAPPEARED and not act.special:
            found = taken or self.lifted(act, env)
            up = self.hand.lifted([env.nodes[n] for n in found[:1]] or targets_of(act, env)[:1])
        return Detection(value=result, found=found, positions=up,
                         position=tuple(float(c) for c in pos) if pos is not None else None)

    def lifted(self, act: ActView, env: EnvModel, hidden: bool = False) -> tuple[str, ...]:
        """The block of the target's stack that the hand really took, () if the target.

        At :Near the hand may be as close to a rider's centre as to its plank's (a cube
        centred on it), and the search then names the rider. Picking a block takes what
        rests on it along: if the block the target rests on (alone) is plainly gone from
        its place too, that one was picked, and so on down. If the target is plainly still
        there, the one block resting on it or standing beside it that is plainly gone was
        (``hidden``: that is not plainly there, when the holder window shows the hand
        holding a block of its size; a block picked in front of a taller one is hidden
        from the side by it, from above by the hand).
        """
        targets = targets_of(act, env)
        if len(targets) != 1:
            return ()
        node, taken = targets[0], None
        while True:
            supports = env.supports_of(node.name)
            below = [n for n in env.get(supports) if n.kind == "Loc"
                     and n.position is not None and n.size is not None]
            if len(supports) != 1 or not below or self.seen(below[0], env) is not False:
                break
            taken = node = below[0]
        if taken is not None:
            return (taken.name,)
        target = targets[0]
        riders = [n for n in env.get(env.supported_by(target.name)) if n.kind == "Loc"
                  and n.position is not None and n.size is not None
                  and env.supports_of(n.name) == [target.name]]
        # ... or of the blocks beside it on its supports: the robot pauses high above a
        # pair touching along x to turn its wrist, and the search named the neighbour
        # (helper round 9, w97)
        level = env.supports_of(target.name)
        beside = [n for n in env.objects() if n.name != target.name and n.position is not None
                  and n.size is not None and n.name not in env.held()
                  and env.supports_of(n.name) == level
                  and footprints_meet(target.position, target.size, n.position, n.size,
                                      -BESIDE_MM)]
        if not riders + beside or self.seen(target, env) is not True:
            return ()
        gone = [n for n in riders + beside
                if self.seen(n, env) in ((False, None) if hidden else (False,))]
        return (gone[0].name,) if len(gone) == 1 else ()

    def holds(self, node: EnvNode, env: EnvModel) -> bool:
        """Whether the holder window shows the hand holding a block of ``node``'s size."""
        if self.hand.hand is None or node.size is None:
            return False
        lift = Region3D.around(self.hand.hand, node.size)
        fill = self.holder.visible_fill((node, lift), env)
        return self.holder.in_hand(lift, env) >= held_bar(fill)

    def seen(self, node: EnvNode, env: EnvModel) -> bool | None:
        """Whether a block is still where the environment model has it (``seen_at``)."""
        return self.sights.seen_at(box(node), {node.name}, env)

    def in_sight(self, act: ActView, env: EnvModel) -> list[Region3D]:
        """Boxes of other known objects in the side camera's line of sight of the motion's
        target: in front, they hide it; behind, they show through where it was (a 19 mm
        cube picked from against another changed 0.096 of the window, where 0.12 was
        asked: lbw bench 1156, the robot watch)."""
        targets = targets_of(act, env)
        if not targets:
            return []
        return boxes_but(env, {n.name for n in targets} | set(env.held()))

    def threshold(self, shot: Snapshot, size: Sequence[float], place: bool = False,
                  others: Sequence[Region3D] = ()) -> float:
        """Area fraction that counts as a change: a third of what the object can change.

        For a pick that is the object's share of the side window, less the part of it
        where other blocks (``others``) project, in front or behind: a 17 mm cube
        behind a two-cube stack showed part of its outline, and its pick changed 0.087
        of the window against the 0.1 asked of a cube in plain view (bench 1157, a PICK
        read as a NO-OP). For
        a place it is the part of the landing box's outline that is dark in the first
        snapshot: where the block, once set down, turns pixels bright (a tall block held
        above its spot is already in view there, one put on a block lands in front of
        its support's bright faces: issue #12, small blocks and pillars).
        """
        cam, region = self.sight.cameras["side"], shot.region
        obj = Region3D.around(region.center, size)
        if place:
            first = shot.pixels["side"]  # the window is on the snapshot's region again
            can = region_mask(cam, obj, self.detector.windows["side"][0]) & \
                (first <= DARK_MAX) & ~band(first, *HAND_BAND)
            share = max(MIN_CHANGE_PX, int(can.sum())) / max(1, first.size)
            return float(min(AREA_THRESHOLD, share / 3.0))
        x0, y0, x1, y1 = cam.box_region(obj.lo, obj.hi)
        w0, v0, w1, v1 = cam.box_region(region.lo, region.hi, margin=1)
        share = max(1, (x1 - x0) * (y1 - y0)) / max(1, (w1 - w0) * (v1 - v0))
        if others:
            window = self.detector.windows["side"][0]
            outline = region_mask(cam, obj, window)
            hidden = regions_mask(cam, others, window)
            total = int(outline.sum())
            if total:
                share *= max(MIN_CHANGE_PX, int((outline & ~hidden).sum())) / total
        return float(min(AREA_THRESHOLD, share / 3.0))


def held_bar(fill: float) -> float:
    """The least block fraction of the holder window that shows a block held, for a block
    whose image fills ``fill`` of it: HOLD_SHARE of that, between EMPTY and HOLDING."""
    return min(HOLDING, max(EMPTY, HOLD_SHARE * fill))
