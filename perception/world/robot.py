"""The robot of Sec. III-4 / VII-B: a Cartesian arm with a parallel-jaw gripper.

It reuses the world's gripper (``perception.world.hand.Gripper``, kind "arm"): the
arm positions the grip centre, the jaws open to a commanded width and close
until both touch a block, which is then held by force-limited joints —
grasping is physical, a badly placed grasp can miss or slip. Commands arrive
in arm coordinates (Fig. 24) and are turned back into world coordinates with
the same calibration the command generator used. Motion is point to point
(Sec. VII-B) along a straight line with a minimum-jerk speed profile; every
world step can be handed to a frame callback, so the execution is rendered
with the same cameras as the demonstration. The wrist turns about the vertical
axis (``turn-wrist``), so the jaws close along x or y; ``push`` is an amove
whose closed jaws push a block ahead of them (the fine motion, docs/execution.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace

from lbw_engine.do.expander import Command
from lbw_engine.rules.commands import ArmFrame
from perception.world.hand import TIP, Gripper, GripperGeometry
from perception.world.physics import World

Vec3 = tuple[float, float, float]
FINGERTIP = TIP  # mm from the grip centre down to the fingertips (commands.yaml gripper.tip)
# The arm stops a downward move when its fingers are pushed back harder than this (g mm/s^2,
# the weight of 0.5 kg): kinematic fingers lowered onto a block dropped in the way crushed
# it into the one below and flung that off the table (helper round 21, f01).
PRESS_LIMIT = 500.0 * 9810.0


@dataclass
class RobotLog:
    """What happened: commands run, grasps made, simulated time."""

    executed: int = 0
    grasps: list[str | None] = field(default_factory=list)  # held block after each close-hand
    time: float = 0.0
    stops: int = 0  # downward moves cut short by the force limit (PRESS_LIMIT)


class Robot:
    """Drives a gripper in a World from manipulator commands."""

    def __init__(self, world: World, frame: ArmFrame, home: Vec3, speed: float = 300.0,
                 dt: float = 1 / 60, on_step: Callable[[World], None] | None = None,
                 finger: Vec3 | None = None, max_opening: float | None = None) -> None:
        """Put the arm's gripper into ``world`` at ``home`` (world mm), jaws open.

        ``finger`` and ``max_opening`` are the finger box and the widest opening the
        command generator planned with (commands.yaml ``gripper``); the robot is
        built with the same.
        """
        self.world = world
        self.frame = frame
        self.speed = speed  # mm/s, peak of the point-to-point profile
        self.dt = dt
        self.on_step = on_step
        geometry = GripperGeometry(finger=tuple(finger)) if finger else GripperGeometry()
        if max_opening is not None:
            geometry = replace(geometry, max_opening=max_opening)
        self.gripper = world.add_gripper(Gripper(tuple(home), opening=80.0, kind="arm",
                                                 geometry=geometry, y_contacts=True))
        self.log = RobotLog()
        # the jaws stopped on something at the last close-hand, and have not opened since:
        # the robot's own sense of holding a block (its jaw width), never the simulator's
        self.gripping = False
        self.current: Command | None = None
        self._do = {"amove": self.amove, "open-hand": self.open_hand,
                    "close-hand": self.close_hand, "turn-wrist": self.turn_wrist,
                    "push": self.amove}

    # -- commands (Sec. VII-B) ----------------------------------------------------
    def execute(self, commands: Iterable[Command]) -> RobotLog:
        """Run commands in order."""
        for c in commands:
            self.current = c  # shown by the execution video
            if c.name not in self._do:
                raise ValueError(f"the robot has no command '{c.name}'")
            if c.arm is not None:
                self._do[c.name](c.arm)
            elif c.width is not None:
                self._do[c.name](c.width)
            elif c.angle is not None:
                self._do[c.name](c.angle)
            else:
                self._do[c.name]()
            self.log.executed += 1
        self.log.time = self.world.time
        return self.log

    def amove(self, arm_xyz: Vec3) -> None:
        """Move the grip centre to an arm-frame point, point to point."""
        start = self.gripper.position
        goal = self.frame.to_world(arm_xyz)
        dist = math.dist(start, goal)
        # Minimum-jerk profile: peak speed 1.875 · dist / T.
        duration = max(0.2, 1.875 * dist / self.speed)
        steps = max(1, math.ceil(duration / self.dt))
        down = goal[2] < start[2] - 1.0
        for k in range(1, steps + 1):
            s = k / steps
            f = 10 * s**3 - 15 * s**4 + 6 * s**5
            self.gripper.move_to(tuple(start[i] + (goal[i] - start[i]) * f for i in range(3)))
            self._step()
            if down and self.gripper.pressing(self.dt / self.world.substeps) > PRESS_LIMIT:
                # a protective stop: the fingers came down on something in the way
                self.gripper.move_to(self.gripper.position)
                self.log.stops += 1
                break
        self._wait(lambda: self.gripper.settled, 1.0)

    @property
    def wrist(self) -> float:
        """The jaws' closing direction now, degrees from world x (the arm's own joint)."""
        return 90.0 * self.gripper.axis

    def turn_wrist(self, angle: float) -> None:
        """Turn the wrist about the vertical: the jaws close along world x (0°) or y (90°)."""
        if abs(angle - 90.0 * round(angle / 90.0)) > 1e-6:
            raise ValueError(f"the wrist turns by quarter turns only, not {angle:g}°")
        self.gripper.turn(round(angle / 90.0) % 2)
        self._wait(lambda: False, 0.2)  # the turn takes a moment

    def open_hand(self, width: float) -> None:
        """Open the jaws to ``width`` mm (releases a held block)."""
        self.gripping = False
        self.gripper.open(width)
        self._wait(lambda: self.gripper.settled, 3.0)
        self._wait(lambda: False, 0.1)  # let a released block come to rest

    def close_hand(self) -> None:
        """Close the jaws until they hold a block or meet."""
        self.gripper.close()
        self._wait(lambda: self.gripper.settled, 3.0)
        self.gripping = self.gripper.opening > 1.0
        self.log.grasps.append(self.gripper.holding)

    # -- stepping -------------------------------------------------------------------
    def _step(self) -> None:
        """One world step, shown to the frame callback."""
        self.world.step(self.dt)
        if self.on_step is not None:
            self.on_step(self.world)

    def _wait(self, done: Callable[[], bool], limit: float) -> None:
        """Step until ``done()`` or ``limit`` seconds passed."""
        t = 0.0
        while not done() and t < limit:
            self._step()
            t += self.dt

    def settle(self, seconds: float) -> None:
        """Let the world run with the arm still (verification waits 2 s)."""
        self._wait(lambda: False, seconds)
