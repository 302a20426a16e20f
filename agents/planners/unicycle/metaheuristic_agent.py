"""``pso-unicycle`` / ``abc-unicycle``: the paper's PSO and ABC optimising the unicycle's own controls.

Every step the agent predicts the obstacles from the observation (``spacetime.SpacetimeModel``: the
env's bounce physics, as ``pso-spacetime`` does), optimises ``n_controls`` normalised targets
``(a_v, a_ω)``, each held ``hold`` steps, with the same compiled PSO or ABC as ``pso-spacetime`` /
``abc-spacetime`` (``pso.pso_run``, ``bee_colony.abc_run``) under the cost of
:mod:`agents.planners.unicycle.rollout` (the env's kinematics rolled out exactly, the paper's
Eq. 4 penalty on predicted contact with obstacles, walls and the arena's edges, the static
cost-to-go past the horizon), and sends the first target as its action.

Warm start: the population holds the previous step's best shifted by one control (what is left of
the plan; with ``hold = 1`` exactly the plan one step on), the previous best as it was (its first
control still held), a pursuit of the goal (or of the cost-to-go's route around walls), braking,
and constant turns at full and zero target speed; the rest is uniform in ``[-1, 1]^2K``. It reads
only the observation and public facts (the robot's limits, ``pathplan_env.robots.unicycle.limits_of``).
"""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np

from agents.base import point_along
from agents.planners.costtogo import route
from agents.planners.metaheuristic import MetaheuristicAgent
from agents.planners.spacetime.astar_agent import SpacetimeModel
from agents.planners.unicycle.rollout import UnicycleScene, broad_phase, rollout, unicycle_params
from pathplan_env.robots.unicycle import arena_edges, command, limits_of, next_velocity, pose

#: ``tuning="crowd"`` (``pso-unicycle-crowd``), for crowds that steer (CrowdNav's circle crossing): the cone
#: of predicted futures and a 10 % margin.
CROWD_SETTINGS = MappingProxyType({"prediction": "cone", "margin": 0.1})
#: Placeholders for the broad phase's fields until :func:`~.unicycle_rollout.broad_phase` fills them.
_NO_DISCS, _NO_GROUPS = np.zeros((0, 0, 3)), np.zeros(0, np.int64)
#: Constant controls ``(a_v, a_ω)`` among the warm-start rows: turns at full and at the lowest target speed.
TURNS = tuple((a_v, a_w) for a_v in (1.0, -1.0) for a_w in (-1.0, -0.5, 0.5, 1.0))


class UnicycleMetaheuristicAgent(MetaheuristicAgent):
    """PSO or ABC over the unicycle's control sequence (the module's doc).

    :param n_controls: controls ``K`` optimised (``2K`` numbers).
    :param hold: steps each control is held (the horizon is ``n_controls * hold`` steps).
    :param margin: relative margin on the contact distance (:class:`~agents.planners.spacetime.SpacetimeModel`).
    :param prediction: the obstacles' prediction (``"physics"`` or ``"cone"``).
    :param turn_weight: weight of the time still needed at the horizon to face the goal.
    :param lookahead: how far along the cost-to-go's route the pursuit row aims (m).

    Every other parameter is :class:`~agents.planners.metaheuristic.MetaheuristicAgent`'s (``population``,
    ``iterations``, ``penalty_weight``, the PSO coefficients, ``abc_limit``, ``warm_start``).

    :raises ValueError: naming the parameter; for an env whose robot is no unicycle.
    """

    def __init__(self, env, seed: int | None = None, *, optimizer: str = "pso", n_controls: int = 5, hold: int = 2, margin: float = 0.005,
                 prediction: str = "physics", turn_weight: float = 0.5, lookahead: float = 1.0, **kwargs):  # fmt: skip
        for label, value in (("n_controls", n_controls), ("hold", hold)):
            if isinstance(value, bool) or int(value) != value or value < 1:
                raise ValueError(f"{label} must be a positive integer, got {value!r}")
        for label, value in (("turn_weight", turn_weight), ("lookahead", lookahead)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"{label} must be a finite number >= 0, got {value!r}")
        self.limits = limits_of(env)
        kwargs.setdefault("warm_start", True)
        kwargs.setdefault("iterations", 20)  # 630 evaluations (PSO), 800 (ABC, 40 bees): ~4 ms a replan
        super().__init__(env, seed, optimizer=optimizer, variant="paper", predictive=True, **kwargs)
        self.n_controls, self.hold = int(n_controls), int(hold)
        self.turn_weight, self.lookahead = float(turn_weight), float(lookahead)
        self.model = SpacetimeModel(self.facts, self.n_controls * self.hold, margin, prediction)
        self.params = unicycle_params(self.limits, self.facts.dt)
        self.control_lo, self.control_hi = -np.ones(2 * self.n_controls), np.ones(2 * self.n_controls)
        self._edges = arena_edges(self.facts.bounds)
        # the warm-start rows that depend on nothing: braking, then the constant turns (built once, not every replan)
        self._constant_rows = np.array([np.tile([-1.0, 0.0], self.n_controls)] + [np.tile(control, self.n_controls) for control in TURNS])

    def problem(self, obs, memory: dict | None = None) -> UnicycleScene:
        """The cost's problem for one observation (walls and cost-to-go kept in ``memory`` while they stay)."""
        segments, ctg = self.model.statics(obs, {} if memory is None else memory)
        trajectory, n, radii, robot, goal = self.model.predict_scene(obs)
        horizon = self.model.horizon_steps
        moves = np.hypot(*np.diff(trajectory[:, :, :2], axis=0).transpose(2, 0, 1))
        travel = np.ascontiguousarray(moves.reshape(horizon, n, -1).sum(axis=1))
        futures = 3 if self.model.prediction == "cone" else 1  # predict_scene's cone: its futures side by side
        speed = float(np.hypot(*np.asarray(obs["robot_velocity"], np.float64)))
        start = np.array([robot[0], robot[1], float(obs["robot_heading"][0]), speed, float(obs["robot_angular_velocity"][0])])
        f = self.facts
        scene = UnicycleScene(trajectory, n, f.robot_radius, radii, start, goal, f.goal_radius, self.params, f.dt, self.hold, horizon,
                              self.penalty_weight, travel, np.vstack([segments.reshape(-1, 5), self._edges]), ctg, self.turn_weight,
                              futures, _NO_DISCS, _NO_GROUPS)  # fmt: skip
        discs, near_segments, near_groups = broad_phase(scene)
        return scene._replace(reach_discs=discs, segments=near_segments, near_groups=near_groups)

    def shifted(self, controls: np.ndarray) -> np.ndarray:
        """The plan one control on: the rest of it, its last control held once more."""
        return np.concatenate([controls[2:], controls[-2:]])

    def pursuit(self, problem: UnicycleScene) -> np.ndarray:
        """Controls that turn toward the goal (or a point ``lookahead`` along the cost-to-go's route)
        at the top turn rate and drive at top speed once facing within 60° of it (slowest before);
        flown with the env's step in plain Python (a compiled call typing the scene would cost more)."""
        x = np.zeros(2 * self.n_controls)
        path = route(problem.cost_to_go, problem.start[:2], problem.goal, 0.5 * self.facts.robot_radius)
        tx, ty = point_along(path, self.lookahead) if problem.cost_to_go.field.size else problem.goal
        lim, dt = self.limits, self.facts.dt
        px, py, heading, v, w = problem.start.tolist()
        for c in range(self.n_controls):
            bearing = math.remainder(math.atan2(ty - py, tx - px) - heading, 2 * math.pi)
            x[2 * c] = 1.0 if abs(bearing) < math.pi / 3 else -1.0
            x[2 * c + 1] = min(max(bearing / (self.hold * dt * lim.max_turn_rate), -1.0), 1.0)
            for _ in range(self.hold):
                v, w = next_velocity(v, w, command(x[2 * c : 2 * c + 2], lim), lim, dt)
                px, py, heading = pose(px, py, heading, v, w, dt, 1.0)
        return x

    def seed_rows(self, problem: UnicycleScene, previous: np.ndarray | None) -> np.ndarray:
        """Warm-start rows after the shifted plan (the module's doc)."""
        rows = [previous] if previous is not None else []
        return np.vstack(rows + [self.pursuit(problem)[None], self._constant_rows])

    def plan(self, obs, memory):
        problem = self.problem(obs, memory)
        previous = memory.get("best")
        if previous is not None:
            memory["best"] = self.shifted(previous)
        best = self.run_optimizer(problem, self.control_lo, self.control_hi, memory, self.seed_rows(problem, previous))
        self.last_plan = rollout(best, problem)[:, :2]
        return best[:2].copy()

    def waypoint_to_action(self, actions: np.ndarray) -> np.ndarray:
        """:meth:`plan` returns the action itself (a normalised target)."""
        return np.clip(actions, -1.0, 1.0).astype(np.float32)


__all__ = ["UnicycleMetaheuristicAgent"]
