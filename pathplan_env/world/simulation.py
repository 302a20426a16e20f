"""The simulated world: pymunk obstacles and walls, a kinematic robot, continuous contact detection.

pymunk (Chipmunk) simulates the obstacles: frictionless, perfectly elastic discs that bounce off
thick static walls on the arena's edges and off each other. Each obstacle keeps its own speed (so
Δd stays exact): contacts change only directions. Obstacles with zero speed are kinematic bodies,
immovable walls to the others. Chipmunk's overlap correction is off, so no obstacle ever moves
farther than its speed allows in a step: Δd holds for displacements, not only for velocities.

The robot is kinematic and never pushes an obstacle, so it is not a pymunk body: the env moves it
in a straight line each step, and robot-obstacle contact is an exact swept-circle test against
the obstacles' positions at every substep (Chipmunk does not sweep; a fast obstacle could
otherwise cross the robot between two steps unseen).

The scene's walls and polygons (``statics.py``) are static pymunk segments, so obstacles bounce off
them as off the arena's edges (and keep their speed the same way); the robot's contact with them
is the same exact swept test (``statics.static_stop``).
"""

from __future__ import annotations

import numpy as np

from pathplan_env.crowds.behaviours import ORCA
from pathplan_env.crowds.routing import drivers_statics
from pathplan_env.geometry.contacts import NO_CONTACT
from pathplan_env.geometry.walls import capsules_clearance, static_stop
from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.world import step_kernel
from pathplan_env.world.chipmunk import READ_BODY, BatchBuffer, address_of, each_body, ffi, function_address, space_step
from pathplan_env.world.routed_call import contiguous, routed_entry, routed_typed
from pathplan_env.world.space import SpaceKeeper, body_pointers
from pathplan_env.world.substep_count import substeps_for
from pathplan_env.world.substep_kernels import _clearance, restore_speeds

_NO_ROBOT = np.empty(0)  # what humans see of an invisible robot
# the C functions the compiled step calls (``step_kernel``)
_STEP = function_address("cpSpaceStep")
_BODY_FUNCTIONS = [function_address(name) for name in ("cpBodySetPosition", "cpBodySetVelocity", "cpBodyGetPosition", "cpBodyGetVelocity")]
_world_step = None  # the compiled step's entry point: compiled (or read from numba's cache) by the first World


def _compile_step() -> None:
    """Compile the world's step once a process, when the first world is built rather than at import
    (``import pathplan_env`` stays fast: ``pathplan-env --help`` does not wait for numba)."""
    global _world_step
    if _world_step is None:
        _world_step = step_kernel.world_step_entry()


_STEER_OUTSIDE, _STEER_ROUTED = step_kernel.STEER_OUTSIDE, step_kernel.STEER_ROUTED  # (read every step: no module lookups)


class World(SpaceKeeper):
    """One episode's simulation, built from a :class:`Scenario` at every reset (its pymunk space new,
    or the previous episode's lent whole: ``pathplan_env.world.space``).

    Obstacle state moves between pymunk and numpy in one batch call per substep from Python
    (``pymunk.batch``), not one Python attribute access per body, and :meth:`step` is one compiled
    call (``pathplan_env.world.step_kernel``): the crowd's steering, Chipmunk's substeps (its bodies
    set and read by Chipmunk's own functions) and the robot's swept test, on the world's arrays
    packed into two (``obstacle_state``, ``radii`` and the speeds are views of one float64 array).
    """

    def __init__(self, scenario: Scenario, recycle: World | None = None):
        """Build the world of ``scenario``; ``recycle`` (the previous episode's world, which is
        emptied and unusable afterwards) lends its whole pymunk space if it fits the scenario (the
        same arena, statics and moving obstacles), else its walls, statics and moving bodies where
        they fit, since creating them was most of a reset. The episode is the same bit for bit
        either way (tested)."""
        _compile_step()
        self.scenario = scenario
        self._diagonal = scenario.arena_diagonal  # the widest gap there is, read every step
        data = scenario.arrays()
        self.radii = data["radii"]
        self.n_obstacles = len(self.radii)
        self._speeds = np.hypot(data["velocities"][:, 0], data["velocities"][:, 1])
        self._drivers = self._group_drivers(scenario)
        self._robot_row = np.array([0.0, 0.0, 0.0, 0.0, scenario.robot_radius])  # what visible humans see
        # the robot's state as Python floats: the env's per-step arithmetic on numpy scalars cost more
        self.robot_xy = (float(scenario.start[0]), float(scenario.start[1]))
        self.robot_velocity_xy = (0.0, 0.0)
        #: A robot that turns (``pathplan_env.robots.unicycle``) keeps its heading (rad), forward speed (m/s)
        #: and turn rate (rad/s) here; the holonomic robot leaves them 0 (sensors read the heading).
        self.robot_heading, self.robot_forward_speed, self.robot_angular_velocity = 0.0, 0.0, 0.0
        self.time = 0.0

        top_speeds = self._speeds if not self._drivers else self._top_speeds()
        self.substeps = substeps_for(top_speeds, self.radii, scenario.dt)
        min_radius = min(self.radii.tolist()) if self.n_obstacles else 1.0

        #: The scene's static geometry inside the arena as capsules, one row ``(x0, y0, x1, y1,
        #: half_thickness)`` each (a wall; a polygon's edges with half-thickness 0). The arena's own
        #: edges are not rows: they are ``scenario.bounds``. Read by sensors and planners.
        self.static_segments = scenario.static_segments
        self._has_statics = len(self.static_segments) > 0  # read every step: no walls, no cost
        # what goal-directed obstacles know of the walls: RVO2 obstacles, routes (routing.py)
        spare = getattr(recycle, "_human_statics", None)  # (its route rows, taken over where they fit: routing._reused_rows)
        self._human_statics = drivers_statics(scenario, self._drivers, spare) if self._drivers and self._has_statics else None
        moving = [speed > 0 for speed in top_speeds.tolist()]  # a goal-directed obstacle is dynamic even at rest
        if recycle is not None and recycle.space is None:  # (a world that lent its space has nothing left)
            recycle = None
        lent = recycle._lend_space(scenario, moving) if recycle is not None else None
        if lent is not None:
            self._take_space(lent, min_radius)
        else:
            self._build_space(scenario, recycle, moving, min_radius)
        # positions and velocities in one batch write; the obstacles are the space's first bodies
        self._pymunk_state[:, :2] = data["positions"]
        self._pymunk_state[:, 2:] = data["velocities"]
        self._write_bodies()
        self.obstacle_state = self._pymunk_state.copy()  # (N, 4): x, y, vx, vy
        self._pack(fresh=True)
        if spare is not None:
            recycle._human_statics = None  # (its rows may be this world's now: never the next one's too)

    @staticmethod
    def _group_drivers(scenario: Scenario) -> list:
        """``(behaviour, obstacle indices, goals, preferred speeds)`` per goal-directed behaviour; empty
        for a scenario of bouncing obstacles (then stepping costs nothing extra)."""
        if not scenario.goal_directed:
            return []
        n = scenario.n_obstacles
        alike = scenario._alike()
        if alike is not None:  # a crowd family's humans: their goals' array kept, one preferred speed
            return [(scenario.behaviour, np.arange(n, dtype=np.int64), alike[3], np.full(n, alike[2]))] if n else []
        if scenario.behaviour.goal_directed and all(ob.behaviour is None for ob in scenario.obstacles):
            groups = {scenario.behaviour: np.arange(n, dtype=np.int64)} if n else {}  # a crowd of one behaviour: the loop's one group
        else:
            groups = {}
            for i in range(n):
                behaviour = scenario.behaviour_of(i)
                if behaviour.goal_directed:
                    groups.setdefault(behaviour, []).append(i)
        goals = np.array([ob.goal if ob.goal is not None else ob.center for ob in scenario.obstacles], np.float64).reshape(n, 2)
        preferred = np.array([ob.preferred_speed for ob in scenario.obstacles], np.float64)
        return [(behaviour, np.array(idx, np.int64), goals, preferred) for behaviour, idx in groups.items()]

    def _top_speeds(self) -> np.ndarray:
        """``scenario.top_speeds()`` from the drivers' arrays: a driver's speed is ``max(speed, preferred)``
        as Python's ``max`` picks (the first unless the second is larger), the others their speed."""
        speeds = self._speeds
        if len(self._drivers) == 1 and len(self._drivers[0][1]) == len(speeds):  # one group of them all (its indices ascending: 0..n-1)
            preferred = self._drivers[0][3]
            return np.where(preferred > speeds, preferred, speeds)
        speeds = speeds.copy()
        for _, idx, _, preferred in self._drivers:
            speeds[idx] = np.where(preferred[idx] > speeds[idx], preferred[idx], speeds[idx])
        return speeds

    def _pack(self, fresh: bool = False) -> None:
        """The arrays :func:`~pathplan_env.world.step_kernel.world_step` reads, packed (``step_kernel``):
        the obstacles' state, speeds, radii, goals and preferred speeds, and the robot's row become
        views of one float64 array, Chipmunk's handles and the ORCA group's indices one int64 array.
        Run at construction (``fresh``: the human statics just built, ``routed_call.routed_typed``'s) and
        after unpickling (the views are copies then)."""
        m, scenario = self.n_obstacles, self.scenario
        mode, idx, behaviour = step_kernel.STEER_NONE, np.empty(0, np.int64), None
        if self._drivers:
            mode = step_kernel.STEER_OUTSIDE
            if len(self._drivers) == 1 and isinstance(self._drivers[0][0], ORCA):
                mode = step_kernel.STEER_ORCA if self._human_statics is None else step_kernel.STEER_ROUTED
                behaviour, idx = self._drivers[0][0], self._drivers[0][1]
        # the routed step through its entry point where the arguments have its types, else the dispatcher
        typed = mode == step_kernel.STEER_ROUTED and routed_typed(self._human_statics, fresh)
        if mode == step_kernel.STEER_ROUTED and not typed and not contiguous(self._human_statics):
            mode = step_kernel.STEER_OUTSIDE  # (the compiled step reads their arrays as C-contiguous)
        self._routed_call = routed_entry() if typed else step_kernel.world_step_routed
        n_order = m + 1 if mode == step_kernel.STEER_ORCA else 0  # ORCA's neighbour order (scratch)
        bodies = step_kernel.INT_HEADER + len(idx) + n_order  # where the cpBody pointers start
        n_ints, n_floats = bodies + m, step_kernel.float_length(m, mode == step_kernel.STEER_ORCA)
        # one allocation, one address (numpy's costs a microsecond): the int64 array, then the float64 one's bits (zeros: 0.0)
        packed = np.zeros(n_ints + n_floats, np.int64)
        ints, floats, address = packed[:n_ints], packed[n_ints:].view(np.float64), address_of(ffi.from_buffer(packed))
        floats[: 4 * m] = self.obstacle_state.ravel()
        floats[4 * m : 5 * m], floats[5 * m : 6 * m] = self._speeds, self.radii
        floats[9 * m : 9 * m + 5] = self._robot_row
        self.obstacle_state, self._speeds, self.radii = floats[: 4 * m].reshape(m, 4), floats[4 * m : 5 * m], floats[5 * m : 6 * m]
        self._robot_row = floats[9 * m : 9 * m + 5]
        goals, preferred = floats[6 * m : 8 * m].reshape(m, 2), floats[8 * m : 9 * m]
        if self._drivers:  # every group shares the goals and preferred speeds
            goals[:], preferred[:] = self._drivers[0][2], self._drivers[0][3]
            self._drivers = [(group, members, goals, preferred) for group, members, _, _ in self._drivers]
        constants = floats[9 * m + 5 :]
        constants[step_kernel.DT], constants[step_kernel.ROBOT_RADIUS] = scenario.dt, scenario.robot_radius
        if behaviour is not None:
            constants[step_kernel.NEIGHBOR_DIST], constants[step_kernel.TIME_HORIZON] = behaviour.neighbor_dist, behaviour.time_horizon
            constants[step_kernel.TIME_HORIZON_OBST] = behaviour.time_horizon_obst
            constants[step_kernel.PAD] = behaviour.radius_padding + behaviour.safety_space  # (as ORCA.steer adds them)
        # the header, the ORCA group's indices, the order's scratch, the obstacles' cpBody pointers (Chipmunk lists their bodies first, as added)
        ints[:] = [address_of(self.space._space), address_of(self._buffer._float_arr), _STEP, self.substeps, mode, m, int(scenario.robot_visible),
                   behaviour.max_neighbors if behaviour else 0, len(idx), address + 8 * n_ints, n_floats, n_ints, *_BODY_FUNCTIONS, bodies,
                   *idx.tolist(), *[0] * n_order, *self._pointers]  # fmt: skip
        self._floats, self._ints, self._mode, self._address = floats, ints, mode, address
        self._sees_robot = mode in (step_kernel.STEER_ORCA, step_kernel.STEER_ROUTED) and scenario.robot_visible
        self._dt = scenario.dt
        self._plain = mode in (step_kernel.STEER_NONE, step_kernel.STEER_ORCA) and not self._sees_robot and not self._has_statics

    def _steer(self) -> None:
        """Goal-directed obstacles choose this step's velocities (all from the same snapshot); the
        speed each chose is the one bounces keep for the step."""
        if self.scenario.robot_visible:
            (x, y), (vx, vy) = self.robot_xy, self.robot_velocity_xy
            robot = self._robot_row
            robot[0], robot[1], robot[2], robot[3] = x, y, vx, vy
        else:
            robot = _NO_ROBOT
        self.steer(robot)

    def steer(self, robots: np.ndarray) -> None:
        """Goal-directed obstacles choose this step's velocities, seeing ``robots`` (``(x, y, vx, vy,
        radius)`` per robot, flattened; empty: none): :meth:`_steer`'s, for a world of several robots."""
        state, dt = self.obstacle_state, self.scenario.dt
        for behaviour, idx, goals, preferred in self._drivers:
            behaviour.steer(idx, state, self._pymunk_state, self._speeds, self.radii, goals, preferred, robots, dt, self._human_statics)
        self._write_bodies()

    # -- stepping ------------------------------------------------------------------------------
    @property
    def robot_position(self) -> np.ndarray:
        return np.array(self.robot_xy)

    @property
    def robot_velocity(self) -> np.ndarray:
        return np.array(self.robot_velocity_xy)

    def step(self, dx: float, dy: float, goal_fraction: float = NO_CONTACT) -> tuple[float, float]:
        """Advance by one ``dt``: move the robot by ``(dx, dy)``, obstacles by physics.

        The robot stops where its episode ends: at ``goal_fraction`` of the move (where it reaches the
        goal; ``NO_CONTACT`` if it does not) or where it first touches an obstacle, whichever comes
        first. The obstacles finish the step; the robot rests at that point with zero velocity.

        Walls and polygons count as obstacles: the robot also stops where it first touches one.

        :return: ``(min_gap, contact_fraction)``: the smallest surface gap to any obstacle, wall or
            polygon during the step up to that point (m; 0 on contact, the arena's diagonal with
            none), and the fraction of the step at which the first contact began (``NO_CONTACT``,
            > 1, if none before the goal).
        """
        x0, y0 = self.robot_xy
        if self._plain:  # no walls, no steering in Python, the humans blind to the robot: the compiled call alone
            self.robot_xy, self.robot_velocity_xy, min_gap, first_contact = _world_step(self._address, x0, y0, dx, dy, goal_fraction, False,
                                                                                        self._diagonal)  # fmt: skip
            self.time += self._dt
            return min_gap, first_contact  # (Python floats from the compiled call)
        min_gap = self._diagonal  # no gap is wider: finite with no obstacles
        static_contact = False
        mode = self._mode
        if mode == _STEER_OUTSIDE:
            self._steer()
        elif self._sees_robot:  # the compiled step steers; the humans see the robot here
            vx, vy = self.robot_velocity_xy
            robot = self._robot_row
            robot[0], robot[1], robot[2], robot[3] = x0, y0, vx, vy
        if self._has_statics:
            # the substeps stop at the walls' first contact as at the goal (an obstacle touched earlier still comes first)
            goal_fraction, static_contact, gap = static_stop(x0, y0, dx, dy, goal_fraction, self.scenario.robot_radius, self.static_segments)
            min_gap = min(min_gap, gap)
        if mode == _STEER_ROUTED:
            min_gap, first_contact = self._step_routed(x0, y0, dx, dy, goal_fraction, static_contact, min_gap)
            self.time += self._dt
            return min_gap, first_contact
        self.robot_xy, self.robot_velocity_xy, min_gap, first_contact = _world_step(self._address, x0, y0, dx, dy, goal_fraction, static_contact,
                                                                                    min_gap)  # fmt: skip
        self.time += self._dt
        return min_gap, first_contact  # (Python floats from the compiled call)

    def _step_routed(self, x0, y0, dx, dy, goal_fraction, static_contact, min_gap) -> tuple[float, float]:
        """:meth:`step`'s compiled call for one ORCA group among walls (their routes computed as the humans need them)."""
        statics = self._human_statics
        args = (self._ints, self._floats, statics.routes_fields, statics.obstacle_fields, statics.scratch_targets, statics.missing,
                (x0, y0, dx, dy, goal_fraction, static_contact, min_gap))  # fmt: skip
        call = self._routed_call
        ax, ay, moving, min_gap, first_contact, n_missing = call(*args)
        while n_missing:  # some human first lost sight of its goal: its route (grid_dijkstra), then the step
            statics.fill_routes(n_missing)
            ax, ay, moving, min_gap, first_contact, n_missing = call(*args)
        self.robot_xy = (ax, ay)
        dt = self._dt
        self.robot_velocity_xy = (dx / dt, dy / dt) if moving else (0.0, 0.0)
        return min_gap, first_contact

    def begin_step(self) -> None:
        """The start of a step driven from outside :meth:`step` (a robot flying arcs): goal-directed
        obstacles choose their velocities."""
        if self._drivers:
            self._steer()

    def advance_obstacles(self) -> tuple[np.ndarray, np.ndarray]:
        """One physics substep of the obstacles: ``(before, after)``, their (N, 4) states (``after`` as
        Chipmunk left it). The caller tests the robot between them and then restores the speeds into
        ``after`` and copies it into ``before`` (``_finish_substep``), calling :meth:`write_bodies` if
        any was restored: the obstacles' half of :meth:`step`'s substep, unchanged."""
        space_step(self.space._space, self.scenario.dt / self.substeps)
        self._buffer._float_arr.num = 0
        each_body(self.space._space, READ_BODY, self._request)
        return self.obstacle_state, self._pymunk_state

    def write_bodies(self) -> None:
        """Write the restored obstacle states back into pymunk (after :meth:`advance_obstacles`)."""
        self._write_bodies()

    def obstacle_trajectory(self, n_steps: int) -> np.ndarray:
        """Advance the obstacles by ``n_steps`` steps and return their state at every substep.

        The robot never moves an obstacle, so unless goal-directed obstacles see it
        (``Scenario.robot_visible``), the obstacles of a fresh world built from an episode's scenario
        follow this trajectory whatever the robot does: it is the future that the privileged
        clairvoyant oracle reads. ``out[s]`` is the (N, 4) state after ``s`` substeps
        (``out[0]`` now); the robot does not move.
        """
        n, dt = self.substeps, self.scenario.dt
        out = np.empty((n_steps * n + 1, self.n_obstacles, 4))
        out[0] = self.obstacle_state
        space, array, request = self.space._space, self._buffer._float_arr, self._request
        for s in range(1, n_steps * n + 1):  # World.step's obstacle half, substep for substep
            if self._drivers and (s - 1) % n == 0:
                self._steer()  # (a visible robot is seen resting where it is)
            space_step(space, dt / n)
            array.num = 0
            each_body(space, READ_BODY, request)
            restored = restore_speeds(self.obstacle_state, self._pymunk_state, self._speeds)  # (no robot to sweep)
            if restored:
                self._write_bodies()
            out[s] = self.obstacle_state
        self.time += n_steps * dt
        return out

    def clearance(self) -> float:
        """Current smallest surface gap between the robot and any obstacle, wall or polygon (the
        arena diagonal with none)."""
        x, y = self.robot_xy
        gap = self.scenario.arena_diagonal
        if self.n_obstacles:
            gap = min(gap, _clearance(self.obstacle_state, self.radii, x, y, self.scenario.robot_radius))
        if self._has_statics:
            gap = min(gap, capsules_clearance(x, y, self.scenario.robot_radius, self.static_segments))
        return gap

    # -- pickling: pymunk's Space pickles itself; the batch buffer and its view are rebuilt ----
    def __getstate__(self):
        state = self.__dict__.copy()
        for key in ("_buffer", "_pymunk_state", "_request", "_floats", "_ints", "_address", "_pointers", "_routed_call"):
            del state[key]
        return state

    def __setstate__(self, state):
        _compile_step()  # (a world unpickled in a fresh process steps too)
        self.__dict__.update(state)
        self._pointers = body_pointers(self._objects)
        self._buffer = BatchBuffer()
        self._attach_state_view()
        self._pack()
