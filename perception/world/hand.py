"""A two-finger gripper driven by position targets: the human hand, later the robot's jaw.

The gripper lives in the world's x-z pymunk plane as kinematic bodies: a grip
frame (no shape) and two fingers (boxes). Its y is kinematic (the world keeps
it outside pymunk). The wrist turns about the vertical axis (design.md
"Robot"), so the jaws close along x or along y:

* along x the fingers are boxes beside the object in x-z, as a 2-D engine
  draws them, and they push a block they meet physically;
* along y both fingers stand at the grip's x-z, each with its own y-range:
  the world's y-extent contact filter then makes a finger touch exactly the
  blocks whose y-range it overlaps, so an open finger passes beside a block
  and lands on one behind it. A finger that reaches a block's face while
  closing pushes it along y (kinematically, as pymunk has no y).

When closing, the fingers stop as soon as both touch the same block; the
block is then attached to the grip frame by a PivotJoint + GearJoint with a
finite maximum force, whichever way the jaws close, so a heavy or badly
grasped block can slip: the grasp is never a weld. Blocks resting on the held
block ride along by friction only (design.md; the plank of Fig. 14).

Coordinates: ``position`` is the grip centre, midway between the fingers'
inner faces, ``TIP`` mm above the fingertips; the palm sits above the fingers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymunk

from perception.world.scene import Box

# The velocity property's own setter: pymunk bodies route every attribute assignment
# through a Python-level __setattr__ (a typing helper that only calls object's); the
# gripper sets three velocities per physics substep.
_set_velocity = pymunk.Body.velocity.fset

Vec3 = tuple[float, float, float]

TIP = 10.0  # mm the fingers reach below the grip centre
CONTACT = 1.0  # mm: a finger this close to a block's side touches it
CLEARANCE = 12.0  # mm per side the demonstrator leaves when pre-shaping the hand
SOFT_CLEARANCE = 2.0  # mm per side when the fingertips squeeze into a tight spot
PINCH = 16.0  # mm of a block's top the squeezing fingertips hold


@dataclass(frozen=True)
class GripperGeometry:
    """Sizes in mm; the HandLoc prism of Table II is about 50 x 50 x 45."""

    finger: tuple[float, float, float] = (10.0, 20.0, 50.0)  # x thickness, y depth, z length
    palm: tuple[float, float, float] = (50.0, 50.0, 30.0)
    max_opening: float = 220.0  # inner gap; the robot's is commands.yaml gripper.max-opening
    close_speed: float = 100.0  # mm/s, finger gap change rate
    grip_strength: float = 25.0  # joint max force, in multiples of the carried weight


def grasp_offset(size: Vec3, soft: bool = False) -> float:
    """Height of the grip centre above a block's centre when grasping it.

    High enough that the fingertips clear the block's support by 1 mm, and at
    most 30 mm below the top so the palm stays above the block. Fingertips
    squeezing into a tight spot (``soft``) pinch its top PINCH mm only: the
    rest of a rigid finger would stand inside the neighbours, hidden from the
    cameras, and the hand-tracker read the hand 5 mm toward the finger still
    in view (lbw bench seed 2076 at 2x, a false ALIGN).
    """
    h = size[2]
    low = max(h / 2 - min(h / 2, 30.0), TIP + 1.0 - h / 2)
    return max(low, h / 2 - PINCH + TIP) if soft else low


def pre_shape(size: Vec3, geometry: GripperGeometry | None = None, axis: int = 0,
              soft: bool = False) -> float:
    """Finger opening used when approaching a block of this size (jaws closing along
    ``axis``); fingertips squeezing into a tight spot (``soft``) open only a little."""
    g = geometry or GripperGeometry()
    return min(g.max_opening, size[axis] + 2 * (SOFT_CLEARANCE if soft else CLEARANCE))


class Gripper:
    """Kinematic two-finger gripper; call ``move_to``/``open``/``close``, the world steps it."""

    def __init__(self, position: Vec3, opening: float = 60.0, kind: str = "hand",
                 geometry: GripperGeometry | None = None, max_speed: float = math.inf,
                 y_contacts: bool = False) -> None:
        """Create the gripper at ``position`` (add it to a World with ``World.add_gripper``).

        ``y_contacts``: its moves along y push what its fingers or held block run
        into (the robot); a scripted hand (the demonstrator) plans clear of blocks
        along y and skips the check, so demonstrations stay as they were.
        """
        self.geometry = g = geometry or GripperGeometry()
        self.kind = kind
        self.max_speed = max_speed  # mm/s; inf = reach each target within one world step
        self.y_contacts = y_contacts
        self.present = True  # an absent gripper is left out of the scene (not in view)
        self.body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.body.position = (position[0], position[2])
        self.y = float(position[1])
        self.target: Vec3 = tuple(map(float, position))
        self.opening = self.target_opening = min(opening, g.max_opening)
        self.axis = 0  # the jaws close along world x (0) or y (1): the wrist's turn
        # A person's fingertips squeeze into a gap narrower than a finger (wrist.py: a hold
        # with no room on either axis): soft fingers push no block, and close only on one
        # that lies wholly between them.
        self.soft = False
        self.world = None
        self.fingers = self._make_fingers()
        self._place_fingers(0.0)
        self.holding: str | None = None
        self.riders: dict[str, float] = {}  # name -> y offset from the grip
        self._joints: list[pymunk.Constraint] = []
        self._hold_dy = 0.0
        self._closing = False

    def _make_fingers(self) -> list[tuple[int, pymunk.Body, pymunk.Shape]]:
        """The two finger bodies; their x-z box depends on the way the jaws close."""
        g = self.geometry
        width = g.finger[0] if self.axis == 0 else g.finger[1]  # extent along x
        fingers = []
        for side in (-1, 1):
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            shape = pymunk.Poly.create_box(body, (width, g.finger[2]))
            shape.friction = 0.8
            shape.side = side
            fingers.append((side, body, shape))
        return fingers

    # -- commands -------------------------------------------------------------
    def turn(self, axis: int) -> None:
        """Turn the wrist so that the jaws close along world x (0) or y (1).

        The held block would turn with the wrist, and boxes stay axis-aligned
        (design.md), so the wrist turns only with empty jaws.
        """
        if axis == self.axis:
            return
        if self.holding is not None:
            raise ValueError("the wrist turns only with empty jaws")
        old, self.axis = self.fingers, axis
        self.fingers = self._make_fingers()
        if self.world is not None:
            self.world.replace_fingers(self, old)
        self._place_fingers(0.0)

    def move_to(self, xyz: Vec3) -> None:
        """Set the grip centre's target position (mm, world frame)."""
        self.target = (float(xyz[0]), float(xyz[1]), float(xyz[2]))

    def open(self, width: float | None = None) -> None:
        """Open to ``width`` mm (default: fully); releases any held block at once."""
        self.target_opening = min(self.geometry.max_opening,
                                  self.geometry.max_opening if width is None else width)
        self._closing = False
        self.world_release()

    def close(self) -> None:
        """Close the fingers until both touch a block (grasp) or they meet."""
        self._closing = True
        self.target_opening = 0.0

    # -- state ----------------------------------------------------------------
    @property
    def position(self) -> Vec3:
        """Current grip centre (mm)."""
        x, z = self.body.position
        return (x, self.y, z)

    @property
    def settled(self) -> bool:
        """Has the gripper reached its position target and finished opening/closing?"""
        p = self.position
        near = math.dist(p, self.target) < 0.5
        return near and (not self._closing) and abs(self.opening - self.target_opening) < 0.5

    def boxes(self) -> list[Box]:
        """Palm and fingers as scene boxes."""
        g = self.geometry
        x, y, z = self.position
        fz = z - TIP + g.finger[2] / 2
        out = [Box(self.kind, (x, y, z - TIP + g.finger[2] + g.palm[2] / 2), g.palm, 0.0, "palm")]
        size = g.finger if self.axis == 0 else (g.finger[1], g.finger[0], g.finger[2])
        for side, body, _ in self.fingers:
            fy = y if self.axis == 0 else sum(self.finger_y_range(side)) / 2
            out.append(Box(self.kind, (body.position[0], fy, fz), size, 0.0,
                           "finger-" + ("left" if side < 0 else "right")))
        return out

    def pressing(self, h: float) -> float:
        """The force (g mm/s^2) the blocks push back on the fingers with, over the last
        physics substep of length ``h`` s: what a wrist force sensor reads."""
        total = [0.0]

        def add(arbiter: pymunk.Arbiter) -> None:
            total[0] += abs(arbiter.total_impulse)

        for _, body, _ in self.fingers:
            body.each_arbiter(add)
        return total[0] / h

    def finger_y_range(self, side: int) -> tuple[float, float]:
        """The y-extent of one finger (mm): the whole depth for x-jaws, its own for y-jaws."""
        g = self.geometry
        if self.axis == 0:
            return self.y - g.finger[1] / 2, self.y + g.finger[1] / 2
        c = self.y + side * (self.opening + g.finger[0]) / 2
        return c - g.finger[0] / 2, c + g.finger[0] / 2

    # -- world side -------------------------------------------------------------
    def attach(self, world) -> None:
        """Called by World.add_gripper: add the bodies to its space."""
        self.world = world
        world.space.add(self.body)
        for _, body, shape in self.fingers:
            world.space.add(body, shape)

    def _place_fingers(self, dt: float, state: tuple[float, float, float, float] | None = None
                       ) -> None:
        """Give the fingers the velocity that brings them to the current opening.

        ``state`` = the hand body's (x, z, vx, vz) when the caller has just read and set
        them (each pymunk property access builds a Vec2d; this runs every substep)."""
        if state is None:
            hx, hz = self.body.position
            vx, vz = self.body.velocity
        else:
            hx, hz, vx, vz = state
        fz = hz - TIP + self.geometry.finger[2] / 2
        half = (self.opening + self.geometry.finger[0]) / 2 if self.axis == 0 else 0.0
        for side, body, _ in self.fingers:
            want = hx + vx * dt + side * half  # y-jaws stand at the grip's x
            if dt > 0:
                _set_velocity(body, ((want - body.position[0]) / dt, vz))
            else:
                body.position = (want, fz)
                body.velocity = (0.0, 0.0)

    def substep(self, start: Vec3, end: Vec3, frac: float, dt: float) -> None:
        """Set velocities for one physics substep toward the interpolated target."""
        x0, _, z0 = start
        tx = x0 + (end[0] - x0) * frac
        tz = z0 + (end[2] - z0) * frac
        px, pz = self.body.position
        vx, vz = (tx - px) / dt, (tz - pz) / dt
        speed = math.hypot(vx, vz)
        if speed > self.max_speed:
            vx, vz = vx * self.max_speed / speed, vz * self.max_speed / speed
        _set_velocity(self.body, (vx, vz))
        if self.opening != self.target_opening:
            step = self.geometry.close_speed * dt
            d = self.target_opening - self.opening
            self.opening += max(-step, min(step, d))
            if self._closing:
                self._check_grasp()
        self._place_fingers(dt, (px, pz, vx, vz))

    def _check_grasp(self) -> None:
        """Stop closing when both fingers touch one block, and hold it."""
        if self.opening <= 0.0:
            self._closing = False  # closed on nothing
            return
        centre = self.body.position[0] if self.axis == 0 else self.y
        left, right = centre - self.opening / 2, centre + self.opening / 2
        name = self.world.between(self, left, right)
        if name is None:
            return
        lo, hi = self.world.extent(name, self.axis)
        if self.axis == 1:
            # A finger at a face pushes the block along y, as one along x does in pymunk.
            push = max(0.0, left - lo) - max(0.0, hi - right)
            if push:
                self.world.shift_y(name, push)
                lo, hi = lo + push, hi + push
        if lo - left <= CONTACT and right - hi <= CONTACT:
            self._closing = False
            self.target_opening = self.opening
            self.world.grasp(self, name)

    def world_release(self) -> None:
        """Drop the held block (remove the grasp joints)."""
        if self._joints:
            self.world.space.remove(*self._joints)
        self._joints = []
        self.holding = None
        self.riders = {}
