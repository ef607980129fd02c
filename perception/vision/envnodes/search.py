"""The guided visual search ENV-node: targets below the hand (Table III :Near, Sec. III-E).

``visual-search`` turns the tracked hand and the environment model into the
stepped 3-D search regions of the sil-finder (perception/vision/vfd/search.py,
Fig. 6) and a found silhouette into the target ENV-nodes it confirms in the
environment model (docs/seeing.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from lbw_engine.model.env import EnvModel, EnvNode
from lbw_engine.model.geometry import footprints_meet
from lbw_engine.names import TABLE
from lbw_engine.see.detectors import Detection, Query
from perception.vision.envnodes.base import EnvNodeBase
from perception.vision.envnodes.hand import box
from perception.vision.vfd.base import Region3D
from perception.vision.vfd.search import SilFinder

TOP_TOLERANCE_MM = 15.0  # confirmed targets: tops within this of the highest one (a support set)
SUPPORT_TOLERANCE_MM = 8.0  # the held block's centre may lie this far off its supports' boxes
# ... and its footprint must reach each support's, both to within this share of its narrower
# side when that is less: a fixed 8 mm is most of a 10 mm cube (issue #12).
SUPPORT_SHARE = 0.3
# The approach is not vertical: at :Near the hand can be 20 mm beside the spot, and it comes
# in over it while it descends (docs/seeing.md). A held centre up to COMING_MM outside a
# level's footprint may still be coming in over it: the decision waits until the held block
# is within DECIDE_MM of that level's top, and is dated back to when the waiting began.
COMING_MM = 30.0
DECIDE_MM = 60.0
# Nor does a centre near a level's edge (not well inside it) decide either way before the
# held block has come down to within LAND_MM of its top: the slant goes on below
# DECIDE_MM, and the tracked hand wanders at pixel 4 / tremor 3. A 10 mm cube held 9 mm
# off the one it went on, 57 mm up, was read as put on the table (helper round 15, AM);
# one tracked 7 mm over its neighbour 59 mm up, as put on it (helper round 16, BE).
LAND_MM = 15.0
TIE_MM = 6.0  # empty hand: candidates this much farther from the hand than the nearest tie
# ... and, while the hand is more than DECIDE_MM above them, any within SLANT_MM of it on
# the far side of the nearest (the hand between them): the approach begins up to 20 mm
# beside its spot, so high up the nearest block need not be the one it comes down to
# (15 mm cubes 25 mm apart, the hand 16 mm from its cube and 10 mm from the neighbour,
# 107 mm up: helper round 20, a PICK read as the neighbour's NO-OP). A hand beyond the
# nearest decides at once, as before (the robot, gripping a 15 mm cube off centre away
# from the one it touches, hovered 7 mm outside it: bench 1050, its PICK unseen)
SLANT_MM = 24.0
# ... but a hand within OVER_MM of the nearest block's centre is over it: the robot comes
# straight down at 270 mm/s, and a search made to wait decided at the grasp, too late for
# its watch to see the PICK (bench 1090: 17 mm cubes 8 mm apart, the hand 4 mm off one).
# A person's slant can also end over the neighbour: 1013 at 2x is read wrong (stop 38).
OVER_MM = 5.0
LEVEL_MM = 5.0  # ... and of those, one whose top is this much higher than another over it
NEAR_SPEED = 1.5  # :Near only while the hand is slower than this many V_H1 (arriving)
MIN_TRANSFER_S = 0.3  # a Transfer (hand lifted, carried, slowed above a target) lasts longer
# A hand carrying an object that stops before it has gone anywhere (x, y) since its
# Transfer began has only lifted it: it is not arriving. Nor is one that speeds up (by
# more than SPEEDING_UP x V_H1 over SPEEDING_S). A person carries on without stopping;
# the robot pauses at every corner of its straight moves, the first at the top of the lift,
# and starts each as slowly as it ends (issue #13, docs/monitor.md).
ARRIVE_MM = 15.0
SPEEDING_S = 0.1
SPEEDING_UP = 0.2
DOWNWARD = 0.7  # a hand whose velocity points down this much (its share of the speed)
# An empty hand that pauses while it rises from where its Transfer began (x, y within
# RISE_MM: it drifts as it lifts), not yet DESCENT_MM below the highest point it reached
# since, is still leaving: at 4x a demonstrator's hand hesitates as it lifts off a placed
# pillar, and the pillar under it was taken for a new target (an extra REACH and NO-OP,
# bench seed 1017). A hand that touched a block and comes back down to pick it has
# descended.
RISE_MM, DESCENT_MM = 30.0, 15.0


class SearchNode(EnvNodeBase):
    """:Near through the sil-finder: stepped regions below the hand (Sec. III-E, Fig. 6)."""

    name = "visual-search"
    calls = {"visual-search": "visual_search"}

    def __init__(self, *args) -> None:
        """A sil-finder on the shared windows."""
        super().__init__(*args)
        self.finder = SilFinder(self.sight.cameras, self.sight.resources)
        self.limit = int(self.rules.constants["search-cycle-limit"])
        self.default = tuple(float(v) for v in self.rules.constants["attention-region"])
        self.last: Region3D | None = None
        self.waiting: dict[float, float] = {}  # query since -> when its search began to wait

    def visual_search(self, query: Query, env: EnvModel) -> Detection | None:
        """Targets found below the arriving hand and confirmed in the environment model."""
        hand = self.hand
        if (hand.hand is None or not hand.steady or hand.speed() > NEAR_SPEED * hand.v_fast
                or self.sight.t - query.since < MIN_TRANSFER_S):
            # a hand that stopped once and sped on (leaving) is not arriving, nor one whose
            # motion has only just begun; just after a re-placement its velocity is unknown
            return None
        if self.leaving(query, env):
            return None
        found = self.near(env)
        if found is WAIT:
            if query.since not in self.waiting:
                self.waiting = {query.since: self.sight.t}  # a new motion: older ones are over
            return None
        return hand.detection(found=found, t=self.waiting.get(query.since)) if found else None

    def leaving(self, query: Query, env: EnvModel) -> bool:
        """A hand carrying an object that has neither gone anywhere since its Transfer began
        nor come down from its highest point since then by DESCENT_MM, or that is speeding
        up, is not arriving; nor is an empty hand still rising above where its Transfer
        began (within RISE_MM, not come down by DESCENT_MM)."""
        hand = self.hand
        start = hand.at(query.since)
        moved = None if start is None else float(np.hypot(*(hand.hand[:2] - start.hand[:2])))
        top = hand.highest(query.since)
        down = top is not None and float(hand.hand[2]) <= float(top.hand[2]) - DESCENT_MM
        if hand.held_box(env, spot=True) is None:
            if moved is None or moved >= RISE_MM:
                return False
            return not down
        if moved is not None and moved < ARRIVE_MM and not down:
            return True  # come back down where it left, it arrives (a carried touch, then
            # the place on the touched block)
        # speeding up on its way down is coming in: a robot stops over the spot for a few
        # frames only, then lowers at 270 mm/s (its monitor, helper round 4, v25b)
        before = hand.at(self.sight.t - SPEEDING_S)
        return before is not None and hand.speed() > before.speed + SPEEDING_UP * hand.v_fast \
            and float(hand.velocity[2]) > -DOWNWARD * hand.speed()

    def regions(self, env: EnvModel) -> tuple[list[Region3D], set[str]]:
        """The search regions, top to bottom, and the names never to report (held, riders)."""
        held = self.hand.held_box(env, spot=True)
        if held is None:
            start = Region3D.around(self.hand.hand, self.default)
            skip: set[str] = set()
            first = 0
        else:
            node, start = held
            skip = {node.name, *env.supported_by(node.name)}
            first = 1  # the held object itself is not a target
            # at least the empty hand's footprint: a 10 mm block held 20 mm beside the
            # spot would otherwise miss the block it is coming in over
            size = np.maximum(start.size, (*self.default[:2], 0.0))
            start = Region3D.around(start.center, size)
        # Footnote 8 steps by the region's height; a thin held plate would then reach only a
        # few cm, so a step is at least the empty hand's region height (docs/seeing.md).
        step = max(float(start.size[2]), self.default[2])
        lo = float(start.lo[2])
        # a held block seen at or below the table top (the tracked hand a few mm low) still
        # has the region under it, which reaches the table (lbw bench 1192: the robot set a
        # 19 mm cube down at the table's corner, 4 mm lower than tracked, with no arrival)
        cycles = min(max(first, math.ceil(lo / step)), self.limit)
        out = []
        for k in range(first, cycles + 1):
            top = lo - (k - 1) * step if k else float(start.hi[2])
            out.append(Region3D((start.lo[0], start.lo[1], top - step if k else lo),
                                (start.hi[0], start.hi[1], top)))
        return out, skip

    def near(self, env: EnvModel) -> tuple[str, ...]:
        """Names of the confirmed targets below the hand, () when none yet, WAIT when a
        held block is still coming in beside a possible support."""
        if self.hand.hand is None:
            return ()
        regions, skip = self.regions(env)
        held = self.hand.held_box(env, spot=True)
        # The held block hangs over the searched place in both views: leave its outline out
        # (grown by 2 mm, for the tremor) so only what lies below it can be found.
        exclude = [] if held is None else [held[1].grown(2.0)]
        # The smallest object that may lie below scales what counts as a silhouette.
        sizes = [n.size for n in env.objects() if n.name not in skip and n.size is not None]
        expect = min(sizes, key=lambda s: float(np.prod(s))) if sizes else None
        coming = False
        for region in regions:
            self.finder.attention(region)
            if self.finder.look(self.sight.frame, exclude, expect) is not None:
                names = self.confirm(region, env, skip, held[1] if held else None)
                if names is WAIT:
                    coming = True
                elif names and coming:
                    # a higher level the held block may still be coming in over has not
                    # decided: nor can a lower one (bench 1157: a small cube held over a
                    # two-cube tower, 70 mm up, was recorded on the tower's lower cube)
                    return WAIT
                elif names:
                    self.last = region
                    return names
            if held is not None and region.lo[2] <= 0.0:
                if coming:
                    return WAIT
                self.last = region  # reached the table with no block below: the table
                return (TABLE,)
        return WAIT if coming else ()

    def grasped(self, hits: Sequence[EnvNode], env: EnvModel) -> tuple[str, ...]:
        """The one block an empty hand is reaching for among the blocks found below it.

        At :Near the hand may still be 20 mm beside the grasp point, so a rider on a
        plank can reach into the hand-sized region before the plank does. The blocks
        found and what they rest on are candidates; the one whose centre is nearest the
        hand wins, the upper one on a near tie of blocks one over another; blocks side
        by side on a near tie wait (WAIT) until the hand is DECIDE_MM above them. While
        it is higher, every block within SLANT_MM of the hand that it lies towards from
        the nearest is on the tie.
        """
        cands = {n.name: n for n in hits}
        todo = list(hits)
        while todo:
            for below in env.get(env.supports_of(todo.pop().name)):
                if below.kind == "Loc" and below.position is not None and below.name not in cands:
                    cands[below.name] = below
                    todo.append(below)
        # the palm-checked point: with the fingers spread the tracked one may be 28 mm off
        # the palm (a lintel across two pillars taken over its middle was named after
        # the pillar under the finger: helper round 18, r70)
        spot = self.hand.spot if self.hand.spot is not None else self.hand.hand
        hand = np.asarray(spot[:2], float)
        # a block with another on it over the hand is not the one taken: its top there is
        # covered (a post under a plate's end, nearer the hand than the plate's centre)
        covered = {name for name in cands if any(
            r.position is not None and r.size is not None and
            bool(np.all(np.abs(np.asarray(r.position[:2]) - hand) <= np.asarray(r.size[:2]) / 2))
            for r in env.get(env.supported_by(name)))}
        cands = {name: n for name, n in cands.items() if name not in covered} or cands
        dist = {name: float(np.hypot(*(np.asarray(n.position[:2]) - hand)))
                for name, n in cands.items()}
        nearest = min(dist, key=dist.__getitem__)
        high = float(self.hand.hand[2]) - max(n.top() for n in cands.values()) > DECIDE_MM \
            and dist[nearest] > OVER_MM
        first = np.asarray(cands[nearest].position[:2], float)
        near = [n for n in cands.values() if dist[n.name] <= dist[nearest] + TIE_MM
                or (high and dist[n.name] <= SLANT_MM  # the hand between it and the nearest
                    and float(np.dot(hand - first, np.asarray(n.position[:2]) - first)) > 0)]
        # of a near tie one over another (a tower's blocks are centred on each other), the
        # upper; side by side, a lower block is no less a candidate (a brick taken from
        # behind a row of taller cubes, 2 mm away: helper round 17, u62)
        pool = [n for n in near if not any(
            m.top() > n.top() + LEVEL_MM and footprints_meet(
                m.position, m.size, n.position, n.size, tol=0.0) for m in near)]
        top = max(n.top() for n in pool)
        if len(pool) > 1 and float(self.hand.hand[2]) - top > DECIDE_MM:
            # blocks side by side, the hand between them: it is still coming in over one
            # (equal cubes 40 mm apart, the approach begun 20 mm beside the target: round
            # 14, v56y read its neighbour's NO-OP)
            return WAIT
        return (min(pool, key=lambda n: dist[n.name]).name,)

    def confirm(self, region: Region3D, env: EnvModel, skip: set[str],
                held: Region3D | None) -> tuple[str, ...]:
        """Loc nodes the found region meets (Sec. III-E step 3): one level of them only.

        With an object in the hand, blocks count as its supports only if its centre is
        over them (their joint footprint): a block beside the spot is not under it. Such
        a block may stand higher than the spot's supports and graze the held footprint
        (a pyramid's upper cube beside the next place): the levels below are tried. A
        centre just outside a level's footprint decides nothing while the held block is
        still high above it (it may be coming in over it): WAIT.
        """
        size = region.size if held is None else \
            np.asarray(region.size) + (2 * SUPPORT_TOLERANCE_MM, 2 * SUPPORT_TOLERANCE_MM, 0.0)
        # a held block's supports may lie up to the support reach outside its footprint
        # (a plate's fourth leg under its edge, 1 mm past the tracked footprint: round 17)
        hits = [n for n in env.nodes_intersecting(region.center, size) if n.name not in skip]
        if not hits:
            return ()
        if held is None:
            # and the blocks below it in the hand's column: a 10 mm cube 6 mm beside a 60 mm
            # block, under the robot's hand, lies below the level where the block's edge is
            # found first (helper round 11, v53h: the pick read as a NO-OP of the block)
            column = Region3D((*region.lo[:2], 0.0), region.hi)
            hits += [n for n in env.nodes_intersecting(column.center, column.size)
                     if n.name not in skip and n not in hits]
            return self.grasped(hits, env)
        while hits:
            top = max(n.top() for n in hits)
            level = [n for n in hits if n.top() >= top - TOP_TOLERANCE_MM]
            # a block under another of the level is no co-support: its top is covered
            # (a 15 mm cube on a 20 mm one, helper round 5's t09: the peg put on the
            # small cube was read as put across both)
            names = {n.name for n in level}
            level = [n for n in level if not names & set(env.supported_by(n.name))]
            hits = [n for n in hits if n not in level]
            if float(held.lo[2]) < top - TOP_TOLERANCE_MM:
                continue  # the held block is already below its top: it comes down beside it
            verdict = self._level(level, held, top)
            if verdict is not None:
                return verdict
        return ()

    @staticmethod
    def _level(level: list[EnvNode], held: Region3D, top: float) -> tuple[str, ...] | None:
        """One level's verdict: its blocks under the held one, WAIT, or None (beside it).

        A support is under the held block: a block of the level that the held footprint
        does not reach (to within a share of its narrower side) is a neighbour beside the
        spot (a small cube set down in the gap of a row), not one end of a bridge over it.
        While the held block is high, its centre must lie well inside the level (by a share
        of the level's narrower side, at most SUPPORT_TOLERANCE_MM): a hand coming in over
        a small neighbour passes over it (issue #12). Only a level no wider than the held
        block asks this: over a wider one (a tower's cube) the hand is where it will land.
        A held block whose footprint reaches the level (to within ``reach``) with its centre
        outside that margin but within COMING_MM decides nothing until it is within LAND_MM
        of the level's top; then a centre within ``reach`` of the level is on it, else
        beside it. One whose footprint does not reach it waits only while high; one whose
        footprint lies more than ``reach`` into one of its blocks waits until landed (the
        level's other blocks, under the far side of a plate, are not under it yet).
        """
        high = float(held.lo[2]) - top > DECIDE_MM
        reach = min(SUPPORT_TOLERANCE_MM, SUPPORT_SHARE * float(min(held.size[:2])))
        gaps = {n.name: _gap(box(n), held) for n in level}
        under = [n for n in level if gaps[n.name] <= reach]
        if not under:
            return WAIT if high and min(gaps.values()) <= COMING_MM else None
        lo = np.min([box(n).lo for n in under], axis=0)[:2]
        hi = np.max([box(n).hi for n in under], axis=0)[:2]
        out = float(np.max(np.maximum(lo - held.center[:2], held.center[:2] - hi)))
        narrow = float(np.min(hi - lo))
        inside = min(SUPPORT_TOLERANCE_MM, SUPPORT_SHARE * narrow) \
            if narrow <= float(min(held.size[:2])) else 0.0
        landed = float(held.lo[2]) - top <= LAND_MM
        # high above the level, a block counts only where the held footprint overlaps it:
        # a 25 mm cube carried in over the spot among four cubes, within reach of all four
        # and centred in their joint footprint, was put on them 130 mm up, and the place
        # began there (helper round 10's v04z, once its grip was measured right)
        over = landed or all(gaps[n.name] < 0.0 for n in under)
        if (out <= -inside and over) or (out <= reach and landed):
            return tuple(n.name for n in under)
        # a footprint well over some of them cannot come down beside them: the supports
        # on its far side are not under it yet (a plate on four posts, each under one of
        # its edges by 5 mm, carried in over two of them 13 mm off its spot)
        deep = min(gaps[n.name] for n in under) < -reach
        return WAIT if (out <= COMING_MM or deep) and not landed else None


def _gap(a: Region3D, b: Region3D) -> float:
    """How far apart the footprints of two boxes are (mm; negative: they overlap)."""
    return float(np.max(np.maximum(np.asarray(a.lo[:2]) - b.hi[:2],
                                   np.asarray(b.lo[:2]) - a.hi[:2])))


WAIT: tuple[str, ...] = ("",)  # no decision yet (a held block coming in beside a level)
