"""The world of several robots: the single env's ``World`` for the obstacles and walls, every robot's
move swept against them and against each other at every physics substep.

The obstacles are the single env's pymunk world, stepped substep by substep
(``World.advance_obstacles``); each robot's contact with them is ``World.step``'s exact swept test
(``geometry.contacts.swept_contact``), its walls ``World.step``'s too (``multi_robot.motion``), and
robot-robot contact an exact swept test of two moving discs (``multi_robot.contacts``). Robots are
not pymunk bodies, as in the single env: an obstacle never bounces off a robot (a contact ends that
robot's episode). Goal-directed obstacles (ORCA humans) see every robot in the world when the
scene's ``robot_visible`` is set.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pathplan_env.geometry.contacts import NO_CONTACT, swept_contact
from pathplan_env.geometry.walls import capsules_clearance
from pathplan_env.multi_robot.contacts import robot_contacts
from pathplan_env.multi_robot.scene import MultiScenario
from pathplan_env.world.simulation import World
from pathplan_env.world.substep_kernels import _clearance, _gap_until, restore_speeds

#: A robot's status: moving toward its goal, resting at it, gone (arrived and left, or collided).
ACTIVE, ARRIVED, LEFT, COLLIDED = 0, 1, 2, 3
_NO_ROBOTS = np.empty(0)


@dataclass
class RobotState:
    """One robot's state (Python floats: the step's arithmetic is per robot)."""

    xy: tuple[float, float]
    velocity: tuple[float, float] = (0.0, 0.0)
    heading: float = 0.0
    forward_speed: float = 0.0
    turn_rate: float = 0.0
    status: int = ACTIVE


@dataclass
class RobotStep:
    """What one step did to one robot: ``goal``/``contact`` are fractions of the step (> 1: none),
    ``hit`` what it touched first (``"robot"``, ``"obstacle"``, ``"wall"`` or ``None``), ``other``
    the robot it touched (its index, -1 if none), ``min_gap`` its smallest surface gap (m)."""

    length: float
    goal: float
    contact: float
    hit: str | None
    other: int
    min_gap: float
    waypoint: tuple[float, float]


class MultiWorld:
    """One episode of a :class:`MultiScenario`.

    :param scene: the scene (its ``arrival`` decides what an arrived robot does).
    """

    def __init__(self, scene: MultiScenario):
        self.scene = scene
        self.scenarios = [scene.robot_scenario(i) for i in range(scene.n_robots)]
        self.world = World(self.scenarios[0])  # the obstacles and walls (its own robot is never moved)
        self.radii = np.array([s.robot_radius for s in self.scenarios])
        self.robots = [RobotState((float(s.start[0]), float(s.start[1]))) for s in self.scenarios]
        for state, s in zip(self.robots, self.scenarios):
            state.heading = math.atan2(s.goal[1] - s.start[1], s.goal[0] - s.start[0])  # a unicycle starts facing its goal
        self._leave = scene.arrival == "leave"
        self._rows = np.empty(5 * scene.n_robots)
        self._sync()

    def _sync(self) -> None:
        """The robots' states as one array and the robots present, kept for the step's readers (the
        observations of every robot read every other's: a per-read rebuild grew with the square of the robots)."""
        self.robot_states = np.array([(*r.xy, *r.velocity) for r in self.robots], np.float64).reshape(-1, 4)
        present = [i for i, r in enumerate(self.robots) if r.status in (ACTIVE, ARRIVED)]
        if present != getattr(self, "_present", None):  # a new list only when the set changes (views compare identity)
            self._present = present

    # -- what observations read ------------------------------------------------------------
    @property
    def time(self) -> float:
        return self.world.time

    @property
    def obstacle_state(self) -> np.ndarray:
        return self.world.obstacle_state

    def present(self) -> list[int]:
        """The robots in the world: moving, or resting at their goal."""
        return self._present

    def robot_rows(self, indices) -> np.ndarray:
        """``(k, 4)`` states ``(x, y, vx, vy)`` of the robots ``indices`` (what the others see of them)."""
        return self.robot_states[list(indices)]

    def _steer(self) -> None:
        world = self.world
        if not world._drivers:
            return
        if world.scenario.robot_visible:
            present = self.present()
            rows = self._rows[: 5 * len(present)]
            for k, i in enumerate(present):
                r = self.robots[i]
                rows[5 * k : 5 * k + 5] = (*r.xy, *r.velocity, self.radii[i])
        else:
            rows = _NO_ROBOTS
        world.steer(rows)

    # -- stepping ----------------------------------------------------------------------------
    def step(self, moves: dict) -> dict[int, RobotStep]:
        """Advance by one ``dt``: every active robot ``i`` flies ``moves[i]`` (``multi_robot.motion``)
        up to where it stops (its goal, a wall, its first contact with an obstacle or a robot); the
        obstacles move by physics. Robots that touched anything are removed; arrived ones rest at
        their goal (or leave, ``arrival="leave"``).

        :return: each moved robot's :class:`RobotStep`.
        """
        world, robots = self.world, self.robots
        self._steer()
        n, dt, radii = world.substeps, world.scenario.dt, world.radii
        count = len(robots)
        present = np.array([r.status in (ACTIVE, ARRIVED) for r in robots])
        movers = [i for i in moves if robots[i].status == ACTIVE]
        a, b = np.empty((count, 2)), np.empty((count, 2))
        for i, r in enumerate(robots):
            a[i] = b[i] = r.xy
        reach, end = self.radii.copy(), np.zeros(count)
        hit, partner, gaps = np.empty(count), np.empty(count, np.int64), np.empty(count)
        out = {}
        moving, goal_substep, min_gap = {}, {}, {}
        for i in movers:
            move = moves[i]
            moving[i] = True
            goal_substep[i] = min(n, max(1, math.ceil(move.stop * n))) if move.stop <= 1.0 else 0
            min_gap[i] = min(world.scenario.arena_diagonal, move.wall_gap)
            out[i] = RobotStep(move.length, NO_CONTACT, NO_CONTACT, None, -1, 0.0, move.waypoint)
        for k in range(1, n + 1):
            before, after = world.advance_obstacles()
            t_obstacle, sweep_gap, goal_gap = {}, {}, {}
            for i in movers:
                if not moving[i]:
                    a[i] = b[i]
                    end[i] = 0.0
                    continue
                move = moves[i]
                b[i] = move.substep(k, n)
                reach[i] = self.radii[i] + move.widening(n)
                ax, ay, bx, by = a[i, 0], a[i, 1], b[i, 0], b[i, 1]
                gap, t = swept_contact(ax, ay, bx, by, reach[i], before, after, radii) if len(radii) else (np.inf, NO_CONTACT)
                sweep_gap[i] = gap
                if k == goal_substep[i]:  # the gap counts up to the stop only
                    goal_here = min(move.stop * n - (k - 1), 1.0)
                    goal_gap[i] = _gap_until(ax, ay, bx, by, goal_here, reach[i], before, after, radii) if len(radii) else np.inf
                    end[i] = goal_here
                else:
                    end[i] = 1.0
                contact = t <= 1.0 and (k - 1 + t) / n <= move.stop
                t_obstacle[i] = t if contact else NO_CONTACT
                if contact:
                    end[i] = min(end[i], t)
            robot_contacts(a, b, end, reach, present, hit, partner, gaps)
            if restore_speeds(before, after, world._speeds):
                world.write_bodies()
            for i in movers:
                if not moving[i]:
                    continue
                move, step = moves[i], out[i]
                t_robot = hit[i] if (hit[i] <= 1.0 and (k - 1 + hit[i]) / n <= move.stop) else NO_CONTACT
                t = min(t_obstacle[i], t_robot)
                if t <= 1.0:  # contact first: the robot stops touching
                    step.contact = (k - 1 + t) / n
                    step.hit = "obstacle" if t_obstacle[i] <= t_robot else "robot"
                    step.other = -1 if step.hit == "obstacle" else int(partner[i])
                    min_gap[i] = 0.0
                    ax, ay = a[i]
                    b[i] = ax + t * (b[i, 0] - ax), ay + t * (b[i, 1] - ay)
                    moving[i] = False
                elif k == goal_substep[i]:  # at the goal, or where it touches a wall
                    if move.wall:
                        step.contact, step.hit, min_gap[i] = move.stop, "wall", 0.0
                    else:
                        step.goal = move.stop
                        min_gap[i] = min(min_gap[i], goal_gap[i], gaps[i])
                    b[i] = move.at(move.stop)
                    moving[i] = False
                else:
                    min_gap[i] = min(min_gap[i], sweep_gap[i], gaps[i])
                a[i] = b[i]
        world.time += dt
        for i in movers:
            r, move, step = robots[i], moves[i], out[i]
            r.xy = (float(a[i, 0]), float(a[i, 1]))
            vx, vy, r.heading, r.forward_speed, r.turn_rate = move.end_state(moving[i], dt, r.heading)
            r.velocity = (vx, vy)
            step.min_gap = float(min_gap[i])
            if step.hit is not None:
                r.status = COLLIDED
            elif step.goal <= 1.0:
                r.status = LEFT if self._leave else ARRIVED
        self._sync()
        return out

    def clearance(self, i: int) -> float:
        """Robot ``i``'s smallest surface gap now to any obstacle, wall or other robot in the world."""
        r = self.robots[i]
        world, (x, y) = self.world, r.xy
        gap = math.inf
        if world.n_obstacles:
            gap = _clearance(world.obstacle_state, world.radii, x, y, float(self.radii[i]))
        if len(world.static_segments):
            gap = min(gap, capsules_clearance(x, y, float(self.radii[i]), world.static_segments))
        for j in self.present():
            if j != i:
                ox, oy = self.robots[j].xy
                gap = min(gap, math.hypot(ox - x, oy - y) - self.radii[i] - self.radii[j])
        return min(gap, world.scenario.arena_diagonal)


__all__ = ["ACTIVE", "ARRIVED", "COLLIDED", "LEFT", "MultiWorld", "RobotState", "RobotStep"]
