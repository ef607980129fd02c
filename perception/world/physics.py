"""The simulated workspace: pymunk in the vertical x-z plane, y kept per block.

design.md's reading of 3-D blocks in a 2-D engine: every block is a pymunk
box in x-z under gravity and keeps its own y-extent; a contact between two
bodies whose y-extents do not overlap is ignored (a begin/pre_solve callback
rejects it), so support, stacking, balance and toppling are physical. The
table spans all of y. Grippers (``perception.world.hand``) are kinematic and driven
by position targets; a held block's y follows its gripper kinematically, and
what the robot's finger or held block runs into along y is pushed ahead of it.

Ground-truth accessors (``positions``, ``relations``) are for evaluation only;
perception's detectors never see this module (tests/test_boundaries.py).
"""

from __future__ import annotations

from collections.abc import Iterable

import pymunk

from lbw_engine.model.geometry import TABLE_X, TABLE_Y, resting_on
from lbw_engine.rules import Roles
from perception.world.balance import block_boxes, tip_along_y
from perception.world.hand import TIP, Gripper
from perception.world.layout import Layout
from perception.world.scene import Box

GRAVITY = 9810.0  # mm/s^2
DENSITY = 0.001  # g/mm^3 (wood-like); masses in g
FRICTION = 0.7

TABLE_CATEGORY = 0b10  # the table's collision category (a block past its edge leaves it)
SLOP = 0.1  # mm: pymunk's resting penetration (Space.collision_slop)
# Solver resolution per 1/30 s frame: at 4 substeps and 10 iterations free-standing towers
# rocked and fell untouched (helper round 15, AG; docs/world.md, tests/world/test_stacks.py)
SUBSTEPS, ITERATIONS = 8, 20
Y_TOUCH = 1e-6  # mm: y-ranges overlapping by no more than this only touch (rounding)
TIE_MM, SPAN_TIE_MM = 1.0, 5.0  # blocks between the jaws: as wide; spanned as far

BLOCK, FINGER = 1, 2  # collision types


def _depth(specs: dict, name: str) -> int:
    """Number of boxes from the table up to and including ``name``."""
    on = [s for s in specs[name].on if s != "table"]
    return 1 + max((_depth(specs, s) for s in on), default=0)


class World:
    """Blocks on a table, plus any grippers; step it with ``step(dt)``."""

    def __init__(self, objects: Iterable, substeps: int = SUBSTEPS) -> None:
        """Build the world from ObjectSpec records (a Workspace's ``objects.values()``)."""
        self.substeps = substeps
        self.time = 0.0
        space = self.space = pymunk.Space()
        space.gravity = (0.0, -GRAVITY)
        space.iterations = ITERATIONS
        space.sleep_time_threshold = 0.3  # resting blocks sleep: cheap idle frames
        self._sleep_s = space.sleep_time_threshold
        space.idle_speed_threshold = 2.0  # mm/s
        space.collision_slop = SLOP
        table = pymunk.Poly(space.static_body, [(TABLE_X[0], -20), (TABLE_X[1], -20),
                                                (TABLE_X[1], 0), (TABLE_X[0], 0)])
        table.friction = FRICTION
        table.filter = pymunk.ShapeFilter(categories=TABLE_CATEGORY)
        space.add(table)
        self.names: list[str] = []
        self.shapes: dict[str, pymunk.Shape] = {}
        self.sizes: dict[str, tuple[float, float, float]] = {}
        self.y: dict[str, float] = {}
        self.grippers: list[Gripper] = []
        self._boxes: dict[str, tuple[float, Box]] = {}  # scene boxes of sleeping blocks
        specs = {spec.name: spec for spec in objects}
        for spec in specs.values():
            # Start each block sunk by the contact slop per level so that its
            # contacts exist from the first step (no initial drop and bounce).
            x, y, z = spec.center
            self.add_block(spec.name, spec.size, (x, y, z - SLOP * _depth(specs, spec.name)))
        for a, b in ((BLOCK, BLOCK), (BLOCK, FINGER)):
            space.on_collision(a, b, begin=self._filter, pre_solve=self._filter)

    def add_block(self, name: str, size, center) -> None:
        """Add a box of ``size`` (x, y, z mm) with its centre at ``center``."""
        sx, sy, sz = map(float, size)
        mass = DENSITY * sx * sy * sz
        body = pymunk.Body(mass, pymunk.moment_for_box(mass, (sx, sz)))
        body.position = (float(center[0]), float(center[2]))
        shape = pymunk.Poly.create_box(body, (sx, sz), radius=0.0)
        shape.friction = FRICTION
        shape.collision_type = BLOCK
        shape.block = name
        self.space.add(body, shape)
        self.names.append(name)
        self.shapes[name] = shape
        self.sizes[name] = (sx, sy, sz)
        self.y[name] = float(center[1])

    def add_gripper(self, gripper: Gripper) -> Gripper:
        """Put a gripper (the human hand or the robot's jaw) into the world."""
        gripper.attach(self)
        self._mark_fingers(gripper)
        self.grippers.append(gripper)
        return gripper

    def replace_fingers(self, gripper: Gripper, old: list) -> None:
        """The wrist turned: the gripper's new finger bodies replace the old ones."""
        for _, body, shape in old:
            self.space.remove(body, shape)
        for _, body, shape in gripper.fingers:
            self.space.add(body, shape)
        self._mark_fingers(gripper)

    @staticmethod
    def _mark_fingers(gripper: Gripper) -> None:
        """Finger shapes collide as fingers and know their gripper (the y filter)."""
        for _, _, shape in gripper.fingers:
            shape.collision_type = FINGER
            shape.gripper = gripper

    def displace(self, name: str, by: tuple[float, float]) -> None:
        """Move a block by (dx, dy) mm (a fault, perception/world/faults.py); riders may
        fall. Along y it stops at a block in the way (pymunk has no y: moved into a post,
        a cube stood inside it, helper round 10, z07). Past the table's y edges it leaves
        the table's category and falls, as past an x edge (round 22: it stood in the air).
        """
        body = self.shapes[name].body
        x, z = body.position
        clear = self._lands_clear(name, float(by[0]), float(by[1]))
        self.y[name] += float(by[1]) if clear else self.free_run_y(name, float(by[1]))
        body.position = (x + float(by[0]), z)  # pymunk parts blocks overlapping in x-z
        if not TABLE_Y[0] <= self.y[name] <= TABLE_Y[1]:
            self.shapes[name].filter = pymunk.ShapeFilter(
                mask=pymunk.ShapeFilter.ALL_MASKS() ^ TABLE_CATEGORY)
        self.space.reindex_shapes_for_body(body)
        self._wake()

    def _lands_clear(self, name: str, dx: float, dy: float) -> bool:
        """Whether ``name`` moved by (dx, dy) meets no other block."""
        bb, (y0, y1) = self.shapes[name].bb, self.extent(name, 1)
        for n in self.names:
            ob, (b0, b1) = self.shapes[n].bb, self.extent(n, 1)
            if n != name and _meet_xz(bb, ob, dx) and min(y1 + dy, b1) - max(y0 + dy, b0) > SLOP:
                return False
        return True

    def free_run_y(self, name: str, dy: float, along: Iterable[str] = ()) -> float:
        """How far (signed, at most ``dy``) ``name`` slides along y before it meets a block
        overlapping it in x-z (not one of those moving ``along`` with it)."""
        bb, (lo, hi) = self.shapes[name].bb, self.extent(name, 1)
        out = dy
        for n in self.names:
            ob, (olo, ohi) = self.shapes[n].bb, self.extent(n, 1)
            if n == name or n in along or not _meet_xz(bb, ob):
                continue  # not level with it, or beside its path: never met
            if dy > 0 and olo >= hi - SLOP:
                out = min(out, max(0.0, olo - hi))
            elif dy < 0 and ohi <= lo + SLOP:
                out = max(out, min(0.0, ohi - lo))
        return out

    def remove_block(self, name: str) -> None:
        """Take a block out of the world (a fault); what rested on it falls."""
        shape = self.shapes.pop(name)
        self.space.remove(shape.body, shape)
        self.names.remove(name)
        del self.sizes[name], self.y[name]
        self._boxes.pop(name, None)
        self._wake()

    def _wake(self) -> None:
        """Wake every block: a support may have gone from under a sleeping one."""
        for shape in self.shapes.values():
            shape.body.activate()

    # -- the y-extent contact filter (design.md) ------------------------------------
    def _y_range(self, shape: pymunk.Shape) -> tuple[float, float]:
        """y-extent of a block or finger shape."""
        name = getattr(shape, "block", None)
        if name is not None:
            half = self.sizes[name][1] / 2
            return self.y[name] - half, self.y[name] + half
        return shape.gripper.finger_y_range(shape.side)

    def _filter(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data) -> None:
        """Ignore contacts of bodies apart in y, of fingers with the block they hold, and of
        soft fingers (a person's, in a tight spot: hand.py) with any block."""
        a, b = arbiter.shapes
        ya, yb = self._y_range(a), self._y_range(b)
        if min(ya[1], yb[1]) - max(ya[0], yb[0]) <= Y_TOUCH:
            arbiter.process_collision = False
            return
        for finger, block in ((b, a), (a, b)):
            g = getattr(finger, "gripper", None)
            if g is not None and (g.soft or g.holding == block.block):
                arbiter.process_collision = False

    # -- stepping ------------------------------------------------------------------
    def step(self, dt: float) -> None:
        """Advance by ``dt`` seconds: grippers move to their targets, physics in substeps."""
        n = self.substeps
        h = dt / n
        starts = [g.position for g in self.grippers]
        for k in range(n):
            for g, start in zip(self.grippers, starts, strict=True):
                g.substep(start, g.target, (k + 1) / n, h)
            self.space.step(h)
        for g in self.grippers:
            if g.target[1] == g.y:
                continue
            if g.y_contacts:
                self._move_y(g, g.target[1])
            else:  # a scripted hand: its path keeps clear of blocks along y
                g.y = g.target[1]
                if g.holding is not None:
                    self.y[g.holding] = g.y + g._hold_dy
                    for name, dy in g.riders.items():
                        self.y[name] = g.y + dy
        tip_along_y(self)  # pymunk has no y: loads hanging past an edge along y tip here
        self.time += dt

    def _move_y(self, g: Gripper, y: float) -> None:
        """The gripper goes to ``y``, its held block and riders with it (pymunk has no y).

        A contact along y is kinematic: a finger or a carried block that runs into
        a block overlapping it in x-z pushes that block ahead of it, as one running
        into it along x does in pymunk (a force-limited hold pushes rather than
        slips against a block on the table: 25 times its weight against friction).
        """
        carried = [g.holding, *g.riders] if g.holding is not None else []
        dy = y - g.y
        movers = [(shape.bb, g.finger_y_range(side)) for side, _, shape in g.fingers]
        movers += [(self.shapes[n].bb, self.extent(n, 1)) for n in carried]
        g.y = y
        left, right = min(bb.left for bb, _ in movers), max(bb.right for bb, _ in movers)
        low = min(bb.bottom for bb, _ in movers)
        near = {}  # blocks whose x-z box meets the movers' x-z span: the only ones in reach
        for n in self.names:
            ob = self.shapes[n].bb
            if ob.top > low + SLOP and ob.right > left + SLOP and ob.left < right - SLOP \
                    and n not in carried:
                near[n] = ob
        for bb, (y0, y1) in movers if near else ():
            self._sweep_y(bb, (y0, y1), (y0 + dy, y1 + dy), near)
        for name in carried:
            self.y[name] += dy

    def _sweep_y(self, bb: pymunk.BB, span0: tuple[float, float], span1: tuple[float, float],
                 among: dict[str, pymunk.BB]) -> None:
        """A box of x-z bounds ``bb`` moved along y from ``span0`` to ``span1``: push the
        blocks ``among`` it runs into (and, through them, the blocks they run into)."""
        d = span1[0] - span0[0]
        if d == 0.0:
            return
        for other, ob in among.items():
            if not _meet_xz(bb, ob):
                continue  # they only graze in x-z: they never meet
            lo, hi = self.extent(other, 1)
            if d > 0 and span0[1] <= lo + Y_TOUCH < span1[1]:
                push = span1[1] - lo
            elif d < 0 and span1[0] < hi - Y_TOUCH <= span0[0]:
                push = span1[0] - hi
            else:
                continue
            rest = {n: b for n, b in among.items() if n != other}
            self._sweep_y(ob, (lo, hi), (lo + push, hi + push), rest)
            self.shift_y(other, push)

    def shift_y(self, name: str, dy: float, riders: Iterable[str] | None = None) -> None:
        """Move a block along y with what rides on it (kinematic: pymunk has no y)."""
        for n in (name, *(self._riders(name) if riders is None else riders)):
            self.y[n] += dy

    def extent(self, name: str, axis: int) -> tuple[float, float]:
        """A block's extent along x (0, its x-z bounds) or y (1), mm."""
        if axis == 0:
            bb = self.shapes[name].bb
            return bb.left, bb.right
        half = self.sizes[name][1] / 2
        return self.y[name] - half, self.y[name] + half

    def settle(self, seconds: float, dt: float = 1 / 30) -> None:
        """Let the world run without commands (e.g. after building a scene)."""
        for _ in range(max(1, round(seconds / dt))):
            self.step(dt)

    # -- gripper services -------------------------------------------------------------
    def between(self, g: Gripper, left: float, right: float) -> str | None:
        """The block between a gripper's fingers, whose inner faces are at ``left`` and
        ``right`` along the jaw axis, within the fingers' reach across it and in z."""
        across = 1 - g.axis
        half = g.geometry.finger[1] / 2  # a finger's depth, across the jaws
        mid = g.y if across == 1 else g.body.position[0]
        fz1 = (fz0 := g.body.position[1] - TIP) + g.geometry.finger[2]
        found = []  # (gap, height spanned, bottom, name)
        for name in self.names:
            bb = self.shapes[name].bb
            lo, hi = self.extent(name, g.axis)
            a0, a1 = self.extent(name, across)
            if hi < left - 1 or lo > right + 1 or bb.top < fz0 or bb.bottom > fz1:
                continue
            if g.soft and (lo < left - 1 or hi > right + 1):
                continue  # a neighbour soft fingers reach into, not one they close on
            if min(a1, mid + half) - max(a0, mid - half) <= 0:
                continue
            reach = min(bb.top, fz1) - max(bb.bottom, fz0)  # how much of it the fingers span
            found.append(((lo - left) + (right - hi), reach, bb.bottom, name))
        if not found:
            return None
        # The best fit; of blocks as wide, those the fingers span most, then the lowest: a
        # cube carrying an equal cube was held by the rider (round 14, v48p), and fingertips
        # grazing the block under the one gripped must not take the tower (review)
        wide = [f for f in found if f[0] <= min(g[0] for g in found) + TIE_MM]
        most = max(f[1] for f in wide)
        return min((f for f in wide if f[1] >= most - SPAN_TIE_MM), key=lambda f: f[2])[3]

    def grasp(self, g: Gripper, name: str) -> None:
        """Attach ``name`` to the gripper with force-limited joints; note its riders."""
        body = self.shapes[name].body
        riders = self._riders(name)
        load = body.mass + sum(self.shapes[r].body.mass for r in riders)
        pivot = pymunk.PivotJoint(g.body, body, body.position)
        pivot.max_force = g.geometry.grip_strength * load * GRAVITY
        gear = pymunk.GearJoint(g.body, body, body.angle - g.body.angle, 1.0)
        gear.max_force = pivot.max_force * max(self.sizes[name][0], 50.0)
        g._joints = [pivot, gear]
        self.space.add(pivot, gear)
        body.activate()
        g.holding = name
        g._hold_dy = self.y[name] - g.y
        g.riders = {r: self.y[r] - g.y for r in riders}

    def _riders(self, name: str) -> list[str]:
        """Blocks resting on ``name`` now, directly or through others."""
        lay = Layout(self.positions(), dict(self.sizes), self.supports())
        return lay.riders(name)

    # -- scene and ground truth -------------------------------------------------------
    def scene(self) -> list[Box]:
        """The renderer's view of the world: blocks, then each present gripper."""
        out = []
        cache = self._boxes
        for name in self.names:
            body = self.shapes[name].body
            y = self.y[name]
            # A body asleep now and when its box was made, less than the sleep time
            # threshold ago, has not moved (pymunk wakes a body that is moved or hit, and
            # a woken body needs that long at rest to sleep again): reuse the box.
            asleep = body.is_sleeping
            prev = cache.get(name)
            if asleep and prev is not None and self.time - prev[0] < self._sleep_s and \
                    prev[1].center[1] == y:
                out.append(prev[1])
                continue
            x, z = body.position
            box = Box("block", (x, y, z), self.sizes[name], body.angle, name)
            if asleep:
                cache[name] = (self.time, box)
            else:
                cache.pop(name, None)
            out.append(box)
        for g in self.grippers:
            if g.present:
                out.extend(g.boxes())
        return out

    def positions(self) -> dict[str, tuple[float, float, float]]:
        """Block centres (mm); ground truth, for evaluation only."""
        xz = {n: self.shapes[n].body.position for n in self.names}
        return {n: (x, self.y[n], z) for n, (x, z) in xz.items()}

    def angles(self) -> dict[str, float]:
        """Block tilts about y (radians); ground truth."""
        return {n: self.shapes[n].body.angle for n in self.names}

    def supports(self) -> dict[str, tuple[str, ...]]:
        """What each block rests on, from geometry: ("table",), supports, or () (held or
        falling): lbw_engine.model.geometry's definition, on each block's bounding box."""
        held = {g.holding for g in self.grippers}
        boxes = block_boxes(self)
        return {name: () if name in held else tuple(resting_on(name, boxes))
                for name in self.names}

    def relations(self, roles: Roles) -> list[list]:
        """Support and holding relations in the actions.json form (ground truth)."""
        lay = Layout(self.positions(), dict(self.sizes), self.supports())
        held = [g.holding for g in self.grippers if g.holding]
        lay.held = held[0] if held else None
        return lay.relations(roles)

    def kinetic(self) -> float:
        """Largest block speed (mm/s); near zero when everything rests."""
        return max((self.shapes[n].body.velocity.length for n in self.names), default=0.0)


def _meet_xz(a: pymunk.BB, b: pymunk.BB, dx: float = 0.0) -> bool:
    """Whether two x-z boxes (``a`` moved by ``dx`` along x) overlap by more than SLOP on
    both axes: blocks that do not could pass each other along y."""
    return min(a.right + dx, b.right) - max(a.left + dx, b.left) > SLOP and \
        min(a.top, b.top) - max(a.bottom, b.bottom) > SLOP
