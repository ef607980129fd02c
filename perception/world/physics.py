"""The simulated workspace: pymunk in the vertical x-z plane, y kept per block.

design.md's reading of 3-D blocks in a 2-D engine: every block is a pymunk
box in x-z under gravity and keeps its own y-extent; a contact between two
bodies whose y-extents do not overlap is ignored (a begin/pre_solve callback
rejects it), so support, stacking, balance and toppling are physical. The
table spans all of y. Grippers (``perception.world.hand``) are kinematic and driven
by position targets; a held block's y follows its gripper kinematically.

Ground-truth accessors (``positions``, ``relations``) are for evaluation only;
perception's detectors never see this module (tests/test_boundaries.py).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import pymunk

from lbw_engine.model.geometry import resting_on
from lbw_engine.rules import Roles
from perception.world.hand import TIP, Gripper
from perception.world.layout import TABLE_X, Layout
from perception.world.scene import Box

GRAVITY = 9810.0  # mm/s^2
DENSITY = 0.001  # g/mm^3 (wood-like); masses in g
FRICTION = 0.7

SLOP = 0.1  # mm: pymunk's resting penetration (Space.collision_slop)

BLOCK, FINGER = 1, 2  # collision types


def _depth(specs: dict, name: str) -> int:
    """Number of boxes from the table up to and including ``name``."""
    on = [s for s in specs[name].on if s != "table"]
    return 1 + max((_depth(specs, s) for s in on), default=0)


class World:
    """Blocks on a table, plus any grippers; step it with ``step(dt)``."""

    def __init__(self, objects: Iterable, substeps: int = 4, iterations: int = 10) -> None:
        """Build the world from ObjectSpec records (a Workspace's ``objects.values()``)."""
        self.substeps = substeps
        self.time = 0.0
        space = self.space = pymunk.Space()
        space.gravity = (0.0, -GRAVITY)
        space.iterations = iterations
        space.sleep_time_threshold = 0.3  # resting blocks sleep: cheap idle frames
        self._sleep_s = space.sleep_time_threshold
        space.idle_speed_threshold = 2.0  # mm/s
        space.collision_slop = SLOP
        table = pymunk.Poly(space.static_body, [(TABLE_X[0], -20), (TABLE_X[1], -20),
                                                (TABLE_X[1], 0), (TABLE_X[0], 0)])
        table.friction = FRICTION
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

    # -- building ----------------------------------------------------------------
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
        for _, _, shape in gripper.fingers:
            shape.collision_type = FINGER
            shape.gripper = gripper
        self.grippers.append(gripper)
        return gripper

    def displace(self, name: str, by: tuple[float, float]) -> None:
        """Slide a block by (dx, dy) mm (a fault, perception/world/faults.py); riders may fall."""
        body = self.shapes[name].body
        x, z = body.position
        body.position = (x + float(by[0]), z)
        self.y[name] += float(by[1])
        self.space.reindex_shapes_for_body(body)
        self._wake()

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
        g = shape.gripper
        half = g.geometry.finger[1] / 2
        return g.y - half, g.y + half

    def _filter(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data) -> None:
        """Ignore contacts of bodies apart in y, and of fingers with the block they hold."""
        a, b = arbiter.shapes
        ya, yb = self._y_range(a), self._y_range(b)
        if min(ya[1], yb[1]) - max(ya[0], yb[0]) <= 0.0:
            arbiter.process_collision = False
            return
        for finger, block in ((b, a), (a, b)):
            g = getattr(finger, "gripper", None)
            if g is not None and g.holding == block.block:
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
            g.y = g.target[1]
            if g.holding is not None:
                self.y[g.holding] = g.y + g._hold_dy
                for name, dy in g.riders.items():
                    self.y[name] = g.y + dy
        self.time += dt

    def settle(self, seconds: float, dt: float = 1 / 30) -> None:
        """Let the world run without commands (e.g. after building a scene)."""
        for _ in range(max(1, round(seconds / dt))):
            self.step(dt)

    # -- gripper services -------------------------------------------------------------
    def between(self, g: Gripper, left: float, right: float) -> str | None:
        """The block between a gripper's fingers (in its y and finger z range), if any."""
        gy0, gy1 = g.y - g.geometry.finger[1] / 2, g.y + g.geometry.finger[1] / 2
        fz0 = g.body.position[1] - TIP
        fz1 = fz0 + g.geometry.finger[2]
        best, best_gap = None, math.inf
        for name in self.names:
            bb = self.shapes[name].bb
            y0, y1 = self.y[name] - self.sizes[name][1] / 2, self.y[name] + self.sizes[name][1] / 2
            if bb.right < left - 1 or bb.left > right + 1 or bb.top < fz0 or bb.bottom > fz1:
                continue
            if min(y1, gy1) - max(y0, gy0) <= 0:
                continue
            gap = (bb.left - left) + (right - bb.right)
            if gap < best_gap:
                best, best_gap = name, gap
        return best

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
        out = {}
        for name in self.names:
            x, z = self.shapes[name].body.position
            out[name] = (x, self.y[name], z)
        return out

    def angles(self) -> dict[str, float]:
        """Block tilts about y (radians); ground truth."""
        return {n: self.shapes[n].body.angle for n in self.names}

    def supports(self) -> dict[str, tuple[str, ...]]:
        """What each block rests on, from geometry: ("table",), supports, or () (held/falling).

        The one definition of lbw_engine.model.geometry, on each block's bounding box
        (a tilted block's box is its shape's x-z bounds and its y-extent).
        """
        held = {g.holding for g in self.grippers}
        boxes = {}
        for name in self.names:
            bb = self.shapes[name].bb
            boxes[name] = (((bb.left + bb.right) / 2, self.y[name], (bb.bottom + bb.top) / 2),
                           (bb.right - bb.left, self.sizes[name][1], bb.top - bb.bottom))
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
