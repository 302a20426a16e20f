"""The static oracle: the exact shortest path among the current obstacles, replanned every step."""

from __future__ import annotations

import math

import numpy as np

from agents.base import Agent, point_along
from agents.base import real_obstacles as real_obstacles  # 0.1.0 public path
from agents.base import real_static_segments as real_static_segments
from agents.observation import Observation
from pathplan_env.geometry.contacts import point_segment_distance, segment_segment_distance
from pathplan_env.geometry.tangent_graph import shortest_path

#: Arc sampling of the planned polyline (m): its chords sink at most ``ARC_RESOLUTION**2 / (8 R)``
#: into a circle of radius ``R`` (1.5e-6 m for R >= 0.33 m), one term of the landing allowance.
ARC_RESOLUTION = 0.002
#: What every margin adds for the robot landing off its planned circle (m): per step at most the
#: polyline's sampling (above), the 1e-6 m a disc holding the robot is shrunk by, and the float32
#: action's rounding (half an ulp of 1 times the arena's half width: 1e-6 m up to 30 m), about
#: 3.5e-6 m; this covers 280 consecutive steps inside one shape's margin, past every preset's time limit.
LANDING_ALLOWANCE = 1e-3

#: The oracle's verdicts: every plan of the episode found a path; some step found none (the robot held still).
VERDICTS = ("path", "no path")


def flying_margin(reach: np.ndarray | float, step_length: float, allowance: float = LANDING_ALLOWANCE) -> np.ndarray:
    """The least margin around a shape of ``reach`` (its radius, or a capsule's half thickness, plus
    the robot's radius: the robot's centre touches it at that distance) that flying the exact path
    in straight steps of at most ``step_length`` needs to never touch it.

    Derivation. The robot lands on the planned path, which keeps ``reach + m`` from the shape's
    centre (or its segment's nearest point ``q``), less the landing error ``a`` (``allowance``).
    A step is a chord of length ``<= s`` (the path between its ends is ``s`` long, the chord no
    longer) whose two ends are at least ``rho = reach + m - a`` from ``q``; the part of its line
    inside the disc of radius ``rho`` about ``q`` is a chord of that disc no longer than ``s``, so the
    step comes no nearer to ``q`` than ``sqrt(rho**2 - s**2 / 4)``. It stays off the shape when that is
    ``> reach``: ``m = sqrt(reach**2 + s**2 / 4) - reach + a`` (about ``s**2 / (8 reach)``: 2.0 cm for a
    0.333 m robot among 0.075 m cylinders at 0.25 m a step, 0.3 cm at 0.1 m a step). The smallest
    shapes need the most; each shape gets its own.
    """
    reach = np.asarray(reach, np.float64)
    return np.sqrt(reach * reach + 0.25 * step_length * step_length) - reach + allowance


class StaticOracleAgent(Agent):
    """Exact shortest collision-free path among the obstacles as they are now and the scene's walls
    and polygons (from the observation's ``static_segments``: capsules inflated by the robot radius
    and a margin; tangent visibility graph + Dijkstra: ``pathplan_env.geometry.shortest_paths.shortest_path``'s graph and path,
    built by ``pathplan_env.geometry.tangent_graph`` fast enough for every step among many shapes);
    flies one step along it.

    Its margin is not tuned: each shape gets :func:`flying_margin`'s, the least with which the
    straight steps along the path never touch it (derived there from the step length, the robot's
    speed limit times ``dt``, and the arc sampling). Where no path exists with those margins the
    robot holds still (a moving obstacle may open one) and the episode's :attr:`verdict` is
    ``"no path"`` (``"path"`` otherwise), which the harness records; it never drives blind at the
    goal. A step is also checked against the shapes before it is flown and shortened if it would
    touch one (only when the robot starts inside a margin, e.g. a start placed closer than it).

    Blind to motion: it is the optimum of a static scene and the yardstick for optimality gaps.
    Where nothing moved since its last plan (the same obstacles, walls and goal, and the robot where
    that plan's step put it, to float32's rounding), the rest of that plan is the shortest path from
    here (a shortest path's every suffix is one): it flies on along it instead of building the graph
    again, so among hundreds of resting discs a replan costs a lookup, not a graph.

    :param margin: a fixed margin (m) for every shape instead of the derived ones (``None``).
    """

    def __init__(self, env, seed=None, *, margin: float | None = None):
        super().__init__(env, seed)
        if margin is not None and not (isinstance(margin, (int, float)) and math.isfinite(margin) and margin >= 0):
            raise ValueError(f"margin must be None or a finite number >= 0, got {margin!r}")
        self.margin = None if margin is None else float(margin)
        self.verdict: str | None = None  # of the episode flown last
        #: Steps of the episode flown last on which no path existed (the robot held still).
        self.no_path_steps = 0

    def _margins(self, reach: np.ndarray) -> np.ndarray:
        return flying_margin(reach, self.step_length) if self.margin is None else np.full(len(reach), self.margin)

    def plan(self, obs, memory):
        if not memory:  # a new episode
            memory["started"] = True
            self.verdict, self.no_path_steps = "path", 0
        robot = np.asarray(obs["robot_position"], np.float64)
        goal = np.asarray(obs["goal"], np.float64)
        centers, _, radii = Observation.of(obs).obstacles
        reach = radii + self.facts.robot_radius
        walls = np.array(Observation.of(obs).covering_walls)  # walls covering the env's exact (float64) ones
        scene = (centers.tobytes(), radii.tobytes(), walls.tobytes(), goal.tobytes())
        kept = memory.get("plan")
        if kept is not None and kept[0] == scene and np.hypot(*(robot - kept[1][0])) <= LANDED:
            return self._fly(memory, scene, np.vstack([robot, kept[1][1:]]), centers, reach, walls)
        inflated = reach + self._margins(reach)
        # never plan around a disc the robot or the goal is already inside: shrink it to fit
        for point in (robot, goal):
            inflated = np.minimum(inflated, np.hypot(*(centers - point).T) - 1e-6)
        capsules = walls.copy()
        capsules[:, 4] += self.facts.robot_radius
        capsules[:, 4] += self._margins(capsules[:, 4])
        for point in (robot, goal):  # as the discs: never plan around a wall the robot or goal is inside
            capsules[:, 4] = np.minimum(capsules[:, 4], point_segment_distance(point[None], capsules[:, 0:2], capsules[:, 2:4]) - 1e-6)
        path, _ = shortest_path(robot, goal, centers, inflated, bounds=self.arena.robot_box, capsules=capsules, arc_resolution=ARC_RESOLUTION)
        self.last_plan = path
        if path is None:  # no path with the margins: hold still and say so
            self.verdict = "no path"
            self.no_path_steps += 1
            memory.pop("plan", None)
            return robot
        return self._fly(memory, scene, path, centers, reach, walls)

    def _fly(self, memory, scene, path, centers, reach, walls) -> np.ndarray:
        """The point one step along ``path``, brought closer while the straight move to it would touch a
        disc (``reach`` from ``centers``) or a wall (the robot's radius beyond its half thickness); the
        rest of the path from it is kept for the next step."""
        self.last_plan = path
        robot, step = path[0], self.step_length
        for _ in range(20):
            target, rest = _split_along(path, step)
            if _clear(robot, target, centers, reach, walls, self.facts.robot_radius):
                memory["plan"] = (scene, rest)
                return target
            step *= 0.5
        memory.pop("plan", None)
        return robot


#: How far (m) the robot may land from its planned point and still fly on along the plan: float32's
#: rounding of the action and the observation (about 1e-6 m in arenas up to 30 m), with room.
LANDED = 1e-5


def _split_along(path: np.ndarray, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """``point_along(path, distance)`` and the polyline from that point to the path's end."""
    target = point_along(path, distance)
    lengths = np.hypot(*np.diff(path, axis=0).T)
    after = int(np.searchsorted(np.cumsum(lengths), distance, side="right")) + 1  # the first vertex beyond the point
    return target, np.vstack([target, path[after:]])


def _clear(a, b, centers, reach, walls, robot_radius) -> bool:
    """Whether the robot's centre moving from ``a`` to ``b`` stays farther than ``reach`` from every
    centre and than ``robot_radius`` beyond every wall's half thickness."""
    if len(reach) and (point_segment_distance(centers, a[None], b[None]) <= reach).any():
        return False
    if len(walls):
        gaps = segment_segment_distance(a[None], b[None], walls[:, 0:2], walls[:, 2:4])
        if (gaps <= walls[:, 4] + robot_radius).any():
            return False
    return True
