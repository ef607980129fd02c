"""The human demonstrator: a scenario's steps as continuous, human-like hand motion.

The hand's targets follow a schedule of segments planned once from the
scenario (symbolic layout, ``perception.world.layout``) and its seed:

| phase     | motion (paper)            | profile                                      |
|-----------|---------------------------|----------------------------------------------|
| transfer  | Transfer (Sec. IV-B)      | fast (~250 mm/s x speed factor), arcing high |
| approach  | LocalMotion / Approach    | slow descent, 10-50 mm/s, slightly slanted   |
| fine      | FineMotion                | grasp / release / touch / align slide        |
| depart    | LocalMotion / Depart      | slow rise, then the next transfer            |
| pause     | hesitation                | the hand stays (tremor only)                 |

Every motion is minimum-jerk with its own random speed factor in
``noise.speed``; tremor (``noise.tremor`` mm) is a smooth sum of sinusoids,
quieter during fine motions. The approach starts at most ~160 mm above the
target's top so the recognizer's visual search (45 mm regions stepped down at
most 4 times, Sec. III-E) can find it. Nothing in the frames marks a segment:
the schedule is only for ground truth (``perception.world.groundtruth``).
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from perception.world.hand import TIP, Gripper, grasp_offset, pre_shape
from perception.world.layout import Layout
from perception.world.physics import SUBSTEPS, World
from perception.world.scene import Box
from perception.world.wrist import hold_axis, slide_path, squeeze_axis

Vec3 = tuple[float, float, float]

V_FAST = 250.0  # mm/s, mean transfer speed (peak 1.875x for minimum jerk)
V_APPROACH = 20.0  # mm/s, mean descent speed: peak stays under Table IV's V_H = 50
V_DEPART = 22.0
V_SLIDE = 12.0
NEAR_LIMIT = 160.0  # mm: approach start above the target's top (visual search reach)
ENTRY = (-480.0, 200.0, 230.0)  # off the table, where the hand comes from and goes to
ABSENT = 1.0  # s without the hand at the start and the end (initial/final state views)
TURN_CLEAR_MM = 10.0  # the fingertips this far above the scene's top when the wrist turns
# mm: the hand's usual ceiling. Over a structure too tall for it, Transfers and approaches
# rise until the fingertips clear its top by TURN_CLEAR_MM, up to VIEW_Z (the palm's top is
# 70 mm above the hand's point, and the side view ends near z 400): a hand held under
# 285 mm swept the top off a 295 mm stack it came to take it from (helper round 15, v64b)
MAX_Z, VIEW_Z = 285.0, 330.0
HOVER = -0.1  # mm: a placed block is let go just touching (the contact slop), no drop
QUIET = 0.1  # tremor scale during fine motions: the fingers do not shake blocks into others
STEADY_RAMP_MM, STEADY_ABOVE_MM, BESIDE_MM = 20.0, 5.0, 15.0  # see _beside_top
CLEAR, CLEAR_TREMOR = 0.5, 0.2  # mm (+ per mm of tremor) a block is let down from one beside it


@dataclass(frozen=True)
class Segment:
    """One planned hand motion: from p0 at t0 to p1 at t1 (minimum jerk, plus an arc)."""

    phase: str  # transfer | approach | fine | depart | pause | absent
    step: int  # demonstration step index; -1 for entering/leaving
    t0: float
    t1: float
    p0: Vec3
    p1: Vec3
    arc: float = 0.0  # mm added to z at mid-path (transfers go high over the table)
    action: tuple = ()  # ("open", width) | ("close",) | ("present", bool) | ("turn", axis)
    #                   | ("soft", bool)
    quiet: bool = False  # tremor reduced (fine motions)
    lateral: str = ""  # "early": sideways part done first (approach), "late": last (depart)
    steady: float = -math.inf  # hand z under which the approach shakes as little as fine motions


def min_jerk(tau: float) -> float:
    """Minimum-jerk position profile s(tau) on [0, 1] (zero end velocity and acceleration)."""
    tau = 0.0 if tau < 0 else 1.0 if tau > 1 else tau
    return tau * tau * tau * (10 - 15 * tau + 6 * tau * tau)


def _add(p: Vec3, d: Vec3) -> Vec3:
    """Vector sum."""
    return (p[0] + d[0], p[1] + d[1], p[2] + d[2])


class _Planner:
    """Builds the segment list for one scenario (all randomness from its seed)."""

    def __init__(self, scenario, rng: np.random.Generator) -> None:
        """Start with the hand absent, then entering from ENTRY."""
        self.sc, self.rng = scenario, rng
        self.t, self.p = ABSENT, ENTRY
        self.segs: list[Segment] = [Segment("absent", -1, 0.0, ABSENT, ENTRY, ENTRY)]
        self.pending: tuple = ("present", True)
        self.axis = 0  # the jaws close along x until a hold needs y (the hand starts so)
        self.soft = False  # the fingertips squeeze in (hand.Gripper.soft)

    def wrist(self, i: int, size: Vec3) -> tuple:
        """Pre-shape actions for the pick or touch at step ``i``: turn the wrist (empty
        hand, during the transfer) when the other side has room and this one has not
        (perception.world.wrist), then open the fingers for the block. Where neither
        side has room (a corner of a grid of blocks a few mm apart), the fingertips
        squeeze in: a rigid finger would shove the neighbours (helper round 10, z04:
        a finished row pushed 40 mm)."""
        axis = hold_axis(self.sc, i)
        squeeze = axis is None
        if squeeze:
            axis = squeeze_axis(self.sc, i)  # room where it is taken, if anywhere
        turn: tuple = ()
        if axis is not None and axis != self.axis:
            turn, self.axis = ("turn", axis), axis
        if squeeze != self.soft:
            self.soft = squeeze
            turn += ("soft", self.soft)
        return turn + ("open", pre_shape(size, axis=self.axis, soft=self.soft))

    def factor(self) -> float:
        """Random speed factor of one motion (noise.speed)."""
        lo, hi = self.sc.noise.speed
        return float(self.rng.uniform(lo, hi))

    def add(self, phase: str, step: int, p1: Vec3, duration: float, arc: float = 0.0,
            action: tuple = (), quiet: bool = False) -> None:
        """Append a segment from the current point to ``p1``."""
        if self.pending:
            action, self.pending = self.pending + action, ()
        # The slant of an approach is taken out early (and put into a depart
        # late) so a held block comes down vertically beside its neighbours.
        lateral = {"approach": "early", "depart": "late"}.get(phase, "")
        self.segs.append(Segment(phase, step, self.t, self.t + duration, self.p, p1, arc,
                                 action, quiet, lateral))
        self.t += duration
        self.p = p1

    def move(self, phase: str, step: int, p1: Vec3, speed: float, action: tuple = (),
             quiet: bool = False, minimum: float = 0.6) -> None:
        """A straight minimum-jerk motion at a mean speed scaled by a random factor."""
        dist = math.dist(self.p, p1)
        self.add(phase, step, p1, max(minimum, dist / (speed * self.factor())), 0.0, action,
                 quiet)

    def transfer(self, step: int, p1: Vec3, top: float, action: tuple = ()) -> None:
        """A fast arcing move high over the table (Transfer)."""
        cruise = max(min(280.0, max(200.0, top + 90.0)), _over(top))
        arc = max(0.0, cruise - max(self.p[2], p1[2]))
        horizontal = math.dist(self.p[:2], p1[:2])
        length = horizontal + 2 * arc + abs(self.p[2] - p1[2])
        self.add("transfer", step, p1, max(1.0, length / (V_FAST * self.factor())), arc, action)

    def hesitate(self, step: int, chance: float = 0.5) -> None:
        """Sometimes stay still for a short while (a human hesitation)."""
        if self.rng.random() < chance:
            self.add("pause", step, self.p, float(self.rng.uniform(0.15, 0.5)), quiet=True)

    def lateral(self, lo: float, hi: float) -> Vec3:
        """A random horizontal offset of lo..hi mm (approach not exactly vertical)."""
        r, a = self.rng.uniform(lo, hi), self.rng.uniform(0, 2 * math.pi)
        return (float(r * math.cos(a)), float(r * math.sin(a)), 0.0)

    def local(self, step: int, grip: Vec3, target_top: float, scene_top: float,
              pre: tuple, fine: list[tuple]) -> None:
        """Transfer above the target, descend to ``grip``, do the fine motions, rise."""
        rise = min(float(self.rng.uniform(100, 140)), NEAR_LIMIT - (grip[2] - target_top),
                   max(MAX_Z, _over(scene_top)) - grip[2])
        above = _add(grip, _add(self.lateral(8, 20), (0, 0, rise)))
        low = self.p[2] - TIP < scene_top + TURN_CLEAR_MM
        if "turn" in pre and low and self.segs[-1].step >= 0:
            # the open fingers turn only above everything: turned 120 mm up beside a 150 mm
            # pillar, they swept it over (helper round 12, 14)
            up = (self.p[0], self.p[1], _over(scene_top))
            self.move("depart", self.segs[-1].step, up, V_DEPART)
        self.transfer(step, above, scene_top, pre)
        self.hesitate(step)
        self.move("approach", step, grip, V_APPROACH)
        for phase, p1, speed, action, minimum in fine:
            self.move(phase, step, p1, speed, action, quiet=True, minimum=minimum)
        self.hesitate(step)
        leave = _add(self.p, _add(self.lateral(5, 15), (0, 0, float(self.rng.uniform(90, 120)))))
        self.move("depart", step, leave, V_DEPART)

    def plan(self) -> list[Segment]:
        """Segments for the whole demonstration."""
        lay = self.sc.teach.layout()
        held_dz, held = 0.0, None
        shifted: dict[str, Vec3] = {}  # where blocks were let down, when not their dest
        for i, step in enumerate(self.sc.demonstration):
            size = lay.size[step.obj]
            top = _scene_top(lay)
            if step.kind == "touch" and held is not None:
                # a touch with a block in hand: that block comes down onto the touched
                # one and is lifted off again, still held (the wrist keeps its turn)
                c = lay.center[step.obj]
                load = lay.size[held]
                grip = (c[0], c[1], c[2] + size[2] / 2 + load[2] / 2 + held_dz + HOVER)
                self.local(i, grip, c[2] + size[2] / 2, top + load[2] + 20.0, (),
                           [("fine", grip, 1.0, (), 0.6)])
            elif step.kind in ("pick", "touch"):
                c = lay.center[step.obj]
                pre = self.wrist(i, size)
                grip = _add(c, (0, 0, grasp_offset(size, self.soft)))
                fine = [("fine", grip, 1.0, ("close",) if step.kind == "pick" else (), 0.6)]
                self.local(i, grip, c[2] + size[2] / 2, top, pre, fine)
                held_dz = grasp_offset(size, self.soft)
                held = step.obj if step.kind == "pick" else held
            else:
                dest = step.dest if step.align is not None else _clear_of_neighbours(
                    lay, step.obj, step.dest, size, CLEAR + CLEAR_TREMOR * self.sc.noise.tremor,
                    shifted)
                shifted[step.obj] = dest
                grip = _add(dest, (0, 0, held_dz + HOVER))
                support_top = step.dest[2] - size[2] / 2
                carried = top + size[2] + 20.0
                fine = []
                if step.align is not None:
                    for point in slide_path(lay, step):
                        fine.append(("fine", _add(point, (0, 0, held_dz + HOVER)), V_SLIDE, (),
                                     0.5))
                fine.append(("fine", fine[-1][1] if fine else grip, 1.0,
                             ("open", pre_shape(size, axis=self.axis, soft=self.soft)), 0.6))
                self.local(i, grip, support_top, carried, (), fine)
                beside = _beside_top(lay, step.obj, dest, size)
                if beside is not None:  # hand z where the block's bottom passes their tops
                    k = max(j for j, g in enumerate(self.segs) if g.step == i
                            and g.phase == "approach")
                    self.segs[k] = replace(self.segs[k], steady=grip[2] - dest[2] + size[2] / 2
                                           + beside + STEADY_ABOVE_MM)
                held = None
            lay = self.sc.states[i]
        exit_point = (math.copysign(480.0, self.p[0] or 1.0), self.p[1], 230.0)
        self.transfer(-1, exit_point, _scene_top(lay))
        self.add("absent", -1, exit_point, ABSENT, action=("present", False))
        return self.segs


def _clear_of_neighbours(lay: Layout, obj: str, dest: Vec3, size: Vec3, gap: float,
                         shifted: dict[str, Vec3]) -> Vec3:
    """``dest`` moved away from each block beside it at its level closer than ``gap`` mm.

    A person sets a block down against another without catching its top edge; the
    held block, let down exactly flush, caught a neighbour's corner with the contact
    slop, hung on it and slid 23 mm off when let go (helper round 8, v66: 40 mm cubes
    laid touching along x), and the symbolic states no longer told what the cameras
    saw. ``shifted``: where earlier blocks were let down instead of their dests (in a row
    laid touching, each is moved from the last one's shifted place). Whether a neighbour
    is near is judged at the places the scenario gives; how far to move, from where the
    neighbour was let down: in a row of four 10 mm cubes the shifts added up, the fourth
    came within the third's shifted place, was taken for no neighbour, and was let down
    on its corner (tests/world/test_demonstrator.py, tiny-row-x-touching)."""
    d = list(dest)
    low, high = dest[2] - size[2] / 2, dest[2] + size[2] / 2
    skip = {obj, *lay.riders(obj)}
    for other, c0 in lay.center.items():
        c, s = shifted.get(other, c0), lay.size[other]
        if other in skip or c[2] + s[2] / 2 <= low + 0.5 or c[2] - s[2] / 2 >= high - 0.5:
            continue  # a support under it, or nothing at its level
        for a in (0, 1):
            if abs(d[1 - a] - c[1 - a]) >= (size[1 - a] + s[1 - a]) / 2:
                continue  # not facing it along this axis
            near = abs(dest[a] - c0[a]) - (size[a] + s[a]) / 2  # as the scenario lays them
            room = abs(d[a] - c[a]) - (size[a] + s[a]) / 2
            if -gap - 0.5 < near < gap and room < gap:
                d[a] += math.copysign(gap - room, dest[a] - c0[a])
    return (d[0], d[1], d[2])


def _beside_top(lay: Layout, obj: str, dest: Vec3, size: Vec3) -> float | None:
    """The highest top of the blocks standing within BESIDE_MM of a block let down at
    ``dest`` and higher than its bottom, but not under it (None: none). A person
    steadies the hand as the block comes down among them: a block shaken 2.5 mm sideways
    while its bottom passed a neighbour's top caught its corner and pushed it 4 mm
    (helper round 8, v66)."""
    low = dest[2] - size[2] / 2
    skip = {obj, *lay.riders(obj)}
    tops = []
    for other, c in lay.center.items():
        s = lay.size[other]
        top = c[2] + s[2] / 2
        if other in skip or top <= low + 0.5:
            continue  # under it, or lower
        if all(abs(dest[a] - c[a]) < (size[a] + s[a]) / 2 + BESIDE_MM for a in (0, 1)):
            tops.append(top)
    return max(tops, default=None)


def _over(top: float) -> float:
    """Hand height whose fingertips clear ``top`` by TURN_CLEAR_MM, at most VIEW_Z."""
    return min(VIEW_Z, top + TIP + TURN_CLEAR_MM)


def _scene_top(lay: Layout) -> float:
    """Height of the tallest box top (mm)."""
    return max((c[2] + lay.size[n][2] / 2 for n, c in lay.center.items()), default=0.0)


class Demonstration:
    """Iterate ``(t, scene)`` per frame of a scenario's demonstration (physics between frames)."""

    def __init__(self, scenario, fps: float = 30.0, substeps: int = SUBSTEPS) -> None:
        """Plan the hand's motion and build the teaching world."""
        self.scenario, self.fps = scenario, float(fps)
        rng = np.random.default_rng(scenario.seed)
        self.segments: list[Segment] = _Planner(scenario, rng).plan()
        self._starts = [seg.t0 for seg in self.segments]
        self._cursor = 0
        self.duration = self.segments[-1].t1
        self.n_frames = int(math.floor(self.duration * self.fps)) + 1
        self.world = World(scenario.teach.objects.values(), substeps=substeps)
        self.hand: Gripper = self.world.add_gripper(Gripper(ENTRY, opening=60.0))
        self.hand.present = False
        amp = scenario.noise.tremor * math.sqrt(2.0 / 3.0)  # 3 sinusoids per axis: std = tremor
        self._tremor = [(amp, rng.uniform(0.4, 1.5, 3) * 2 * math.pi, rng.uniform(0, 6.3, 3))
                        for _ in range(3)]

    def planned(self, t: float) -> Vec3:
        """The planned hand position at any time ``t``, without tremor (ground truth)."""
        k = max(0, bisect.bisect_right(self._starts, t) - 1)
        return self._along(self.segments[k], t)

    def target(self, t: float) -> tuple[Vec3, Segment]:
        """Planned hand position at time ``t`` (with tremor) and its segment."""
        seg = self._segment(t)
        p = list(self._along(seg, t))
        scale = QUIET if seg.quiet else 1.0
        if seg.phase in ("approach", "depart"):
            # fade towards the fine motion so the tremor does not jump at its ends
            d = seg.t1 - seg.t0
            s = min_jerk((t - seg.t0) / d) if d > 0 else 1.0
            u = s if seg.phase == "depart" else 1.0 - s
            scale = QUIET + (1 - QUIET) * min(1.0, 3.0 * u)
            if seg.phase == "approach":  # steady once the block comes down among neighbours
                scale = min(scale, QUIET + (1 - QUIET) * min(1.0, max(
                    0.0, (p[2] - seg.steady) / STEADY_RAMP_MM)))
        for axis, (amp, w, ph) in enumerate(self._tremor):
            p[axis] += scale * amp * sum(math.sin(w[k] * t + ph[k]) for k in range(3))
        return (p[0], p[1], p[2]), seg

    def _along(self, seg: Segment, t: float) -> Vec3:
        """Where segment ``seg`` has the hand at ``t`` (minimum jerk, arc, lateral timing)."""
        d = seg.t1 - seg.t0
        s = min_jerk((t - seg.t0) / d) if d > 0 else 1.0
        sl = s if not seg.lateral else 1 - (1 - s) ** 3 if seg.lateral == "early" else s ** 3
        p0, p1 = seg.p0, seg.p1
        return (p0[0] + (p1[0] - p0[0]) * sl, p0[1] + (p1[1] - p0[1]) * sl,
                p0[2] + (p1[2] - p0[2]) * s + seg.arc * math.sin(math.pi * s))

    def _segment(self, t: float) -> Segment:
        """The segment running at ``t`` (the last one after the end)."""
        i = self._cursor
        while i + 1 < len(self.segments) and self.segments[i].t1 <= t:
            i += 1
        self._cursor = i
        return self.segments[i]

    def __iter__(self) -> Iterator[tuple[float, list[Box]]]:
        """Frames in time order: (t seconds, scene)."""
        self._cursor = 0
        started = 0
        dt = 1.0 / self.fps
        for i in range(self.n_frames):
            t = i * dt
            while started < len(self.segments) and self.segments[started].t0 <= t:
                self._act(self.segments[started].action)
                started += 1
            if i:
                pos, _ = self.target(t)
                self.hand.move_to(pos)
                self.world.step(dt)
            yield t, self.world.scene()

    def _act(self, action: tuple) -> None:
        """Run a segment's hand actions (open/close/turn/appear/disappear)."""
        k = 0
        while k < len(action):
            if action[k] == "open":
                self.hand.open(action[k + 1])
                k += 2
            elif action[k] == "close":
                self.hand.close()
                k += 1
            elif action[k] == "turn":
                self.hand.turn(action[k + 1])
                k += 2
            elif action[k] == "soft":
                self.hand.soft = action[k + 1]
                k += 2
            else:  # "present": the hand comes into / goes out of the workspace
                self.hand.present = action[k + 1]
                k += 2
