"""The simulated world: pymunk obstacles and walls, a kinematic robot, continuous contact detection.

pymunk (Chipmunk) simulates the obstacles: frictionless, perfectly elastic discs that bounce off
thick static walls on the arena's edges and off each other. Each obstacle keeps its own speed (so
Δd stays exact): contacts change only directions. Obstacles with zero speed are kinematic bodies,
immovable walls to the others.

The robot is kinematic and never pushes an obstacle, so it is not a pymunk body: the env moves it
in a straight line each step, and robot-obstacle contact is an exact swept-circle test against
the obstacles' positions at every substep (Chipmunk does not sweep; a fast obstacle could
otherwise cross the robot between two steps unseen).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk
import pymunk.batch

from .geometry import NO_CONTACT, swept_contact
from .scenarios import Scenario

OBSTACLE_TYPE = 1
WALL_TYPE = 2
#: Largest obstacle displacement per substep, in units of the smallest obstacle radius. Keeps
#: Chipmunk's discrete collision detection from missing obstacle-obstacle and obstacle-wall
#: contacts; robot contacts are exact at any substep size.
MAX_SUBSTEP_DISPLACEMENT = 0.5
_STATE_FIELDS = pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.VELOCITY


@dataclass(frozen=True)
class StepContact:
    """What the robot met during one step."""

    min_gap: float
    """Smallest surface gap to any obstacle during the step (m); negative on contact; inf if none."""
    contact_fraction: float
    """Fraction of the step at which the first contact began; ``NO_CONTACT`` (> 1) if none."""

    @property
    def collided(self) -> bool:
        return self.contact_fraction <= 1.0


class World:
    """One episode's simulation, built fresh from a :class:`Scenario` (as LunarLander does on reset)."""

    def __init__(self, scenario: Scenario):
        self.scenario = scenario
        data = scenario.arrays()
        self.radii = data["radii"]
        self.n_obstacles = len(self.radii)
        self._nominal_speed = np.linalg.norm(data["velocities"], axis=1)
        self.robot_position = np.array(scenario.start, dtype=np.float64)
        self.robot_velocity = np.zeros(2)
        self.time = 0.0

        max_displacement = float(self._nominal_speed.max(initial=0.0)) * scenario.dt
        min_radius = float(self.radii.min(initial=1.0))
        self.substeps = max(1, math.ceil(max_displacement / (MAX_SUBSTEP_DISPLACEMENT * min_radius)))

        self.space = pymunk.Space()
        self.space.collision_slop = 1e-4 * min_radius  # default 0.1 m is a fifth of a small obstacle
        self._add_walls(scenario.bounds, thickness=max(scenario.arena_diagonal, 1.0))
        self._bodies = []
        for (x, y), (vx, vy), r, speed in zip(data["positions"], data["velocities"], self.radii, self._nominal_speed):
            if speed > 0:
                body = pymunk.Body(mass=r * r, moment=math.inf)  # equal density; discs never spin
            else:
                body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)  # a resting obstacle is immovable
            body.position = (float(x), float(y))
            body.velocity = (float(vx), float(vy))
            shape = pymunk.Circle(body, float(r))
            shape.elasticity, shape.friction, shape.collision_type = 1.0, 0.0, OBSTACLE_TYPE
            self.space.add(body, shape)
            self._bodies.append(body)
        self._touched: set[int] = set()
        self.space.on_collision(OBSTACLE_TYPE, None, post_solve=self._record_contact)
        self._init_buffers()
        self._read_state()
        self.obstacle_state = self._states[self._current]  # (N, 4): x, y, vx, vy

    # -- construction helpers ------------------------------------------------------------------
    def _add_walls(self, bounds, thickness: float) -> None:
        """Four thick static walls whose inner faces are the arena's edges (no tunnelling through them)."""
        xmin, ymin, xmax, ymax = bounds
        h = thickness
        walls = self.space.static_body
        segments = [
            ((xmin - h, ymin - h), (xmax + h, ymin - h)),
            ((xmin - h, ymax + h), (xmax + h, ymax + h)),
            ((xmin - h, ymin - h), (xmin - h, ymax + h)),
            ((xmax + h, ymin - h), (xmax + h, ymax + h)),
        ]
        for a, b in segments:
            seg = pymunk.Segment(walls, a, b, h)
            seg.elasticity, seg.friction, seg.collision_type = 1.0, 0.0, WALL_TYPE
            self.space.add(seg)

    def _init_buffers(self) -> None:
        # Two state arrays we alternate between: the previous substep's state stays intact for the
        # swept test without a copy. (pymunk.batch's set_float_buf would let pymunk write into them
        # directly, but in pymunk 7.3 it does not keep its view alive, so we copy from its buffer.)
        self._buffer = pymunk.batch.Buffer()
        self._states = [np.zeros((self.n_obstacles, 4)), np.zeros((self.n_obstacles, 4))]
        self._current = 0

    def _read_state(self) -> None:
        buf = self._buffer
        buf.clear()
        pymunk.batch.get_space_bodies(self.space, _STATE_FIELDS, buf)
        # dynamic and kinematic bodies come first, in insertion order: the obstacles
        flat = np.frombuffer(buf.float_buf(), dtype=np.float64, count=4 * self.n_obstacles)
        self._states[self._current][:] = flat.reshape(self.n_obstacles, 4)

    def _record_contact(self, arbiter: pymunk.Arbiter, space, data) -> None:
        for shape in arbiter.shapes:
            if shape.collision_type == OBSTACLE_TYPE:
                self._touched.add(id(shape.body))

    def _restore_speeds(self) -> None:
        """Give every obstacle touched in the last substep its own speed back (directions unchanged)."""
        for index, body in enumerate(self._bodies):
            if id(body) in self._touched:
                vx, vy = body.velocity
                norm = math.hypot(vx, vy)
                if norm > 0:
                    scale = self._nominal_speed[index] / norm
                    body.velocity = (vx * scale, vy * scale)
        self._touched.clear()

    # -- stepping ------------------------------------------------------------------------------
    def step(self, robot_displacement: tuple[float, float]) -> StepContact:
        """Advance by one ``dt``: move the robot by ``robot_displacement``, obstacles by physics."""
        dt = self.scenario.dt
        n = self.substeps
        dx, dy = robot_displacement
        start = self.robot_position
        min_gap, first_contact = math.inf, NO_CONTACT
        robot_a = start
        for k in range(1, n + 1):
            self.space.step(dt / n)
            if self._touched:
                self._restore_speeds()
            previous = self._states[self._current]
            self._current ^= 1
            self._read_state()
            robot_b = start + (k / n) * np.array((dx, dy)) if n > 1 else start + (dx, dy)
            gap, t = swept_contact(robot_a, robot_b, self.scenario.robot_radius, previous, self._states[self._current], self.radii)
            min_gap = min(min_gap, gap)
            if t <= 1.0 and first_contact > 1.0:
                first_contact = (k - 1 + t) / n
            robot_a = robot_b
        self.obstacle_state = self._states[self._current]
        self.robot_position = robot_a
        self.robot_velocity = np.array((dx / dt, dy / dt))
        self.time += dt
        return StepContact(min_gap=float(min_gap), contact_fraction=float(first_contact))

    def clearance(self) -> float:
        """Current smallest surface gap between the robot and any obstacle (inf with no obstacles)."""
        if self.n_obstacles == 0:
            return math.inf
        d = np.hypot(*(self.obstacle_state[:, :2] - self.robot_position).T) - self.radii - self.scenario.robot_radius
        return float(d.min())

    # -- pickling: pymunk's Space pickles itself; the batch buffer is rebuilt ------------------
    def __getstate__(self):
        state = self.__dict__.copy()
        del state["_buffer"]
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._buffer = pymunk.batch.Buffer()
        self.obstacle_state = self._states[self._current]
