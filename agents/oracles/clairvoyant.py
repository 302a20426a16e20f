"""``oracle-clairvoyant``: the physical limit of an episode. PRIVILEGED: it reads the simulator.

Not a policy anyone could deploy, and the only agent allowed to look past the observation: it
reads the episode's :class:`~pathplan_env.Scenario` from the env and steps a fresh copy of the
world ahead, which gives every obstacle's position at every substep of the episode
(:mod:`agents.oracles.future`: the robot never moves an obstacle, so that future does not depend
on what the robot does). When the env's robot is a unicycle, ``ClairvoyantOracle(env)`` is the
unicycle's oracle (:mod:`agents.oracles.clairvoyant_unicycle`), which searches the unicycle's own
moves on the same future. Otherwise it searches
(step, position) for the earliest collision-free arrival (:mod:`agents.planners.spacetime.astar`:
the scene's walls and polygons in its contact test and its lost-episode proof, its heuristic the
static cost-to-go around them and the obstacles that never move) and flies the plan, which
replays exactly because every move was made with the env's own kinematics and contact test. The
evaluation harness runs it on every cell's episodes to report the ``limit``.

Where goal-directed obstacles see the robot (``Scenario.robot_visible``), their future depends on
what the robot does and no fixed trajectory bounds it: the oracle then plans against the future
they would have without the robot, says so (verdict ``"reactive"``) and gives no limit.
"""

from __future__ import annotations

import time

import numpy as np

from agents.base import Agent
from agents.oracles.clairvoyant_unicycle import UnicycleClairvoyantOracle
from agents.oracles.future import simulator_of, true_future
from agents.planners.reachable_set import provably_lost
from agents.planners.spacetime.astar import BUDGET, FOUND, SearchSettings, SpacetimeProblem, heading_moves, search
from pathplan_env.robots.unicycle import UnicycleAction

#: What the oracle concludes about an episode: a plan, provably no plan, a failed search, or no
#: limit because the obstacles react to the robot.
VERDICTS = ("plan", "lost", "undetermined", "reactive")


class ClairvoyantOracle(Agent):
    """Earliest-arrival plan against the obstacles' true future. **Reads the simulator.**

    :param n_headings: move directions per node (evenly spaced).
    :param speed_fractions: move lengths, as fractions of the robot's step (waiting and a move
        onto the goal are always tried too).
    :param searches: the successive searches, ``(heuristic weight, merge grid in m)`` each: a search
        that spends ``max_expansions`` without an answer hands over to the next (weighted A*: weight 3
        finds plans fast; 1.5 gets out of dead ends where the greedy one spends its budget; a coarser
        grid reaches farther in slow, cluttered scenes, where fine cells multiply the nodes).
    :param max_expansions: node budget of each search; after the last the episode is
        "undetermined" unless the reachable-set test proves it lost.
    :param lost_cell: grid (m) of that reachable-set test.
    """

    def __new__(cls, *args, **kwargs):
        # the limit searches the env's own robot's moves: a unicycle's env gets the unicycle's oracle,
        # built whole here (one name, ``oracle-clairvoyant``, is the harness's limit for every robot)
        env = args[0] if args else kwargs.get("env")
        if cls is ClairvoyantOracle and isinstance(getattr(getattr(env, "unwrapped", None), "action_type", None), UnicycleAction):
            return UnicycleClairvoyantOracle(*args, **kwargs)
        return super().__new__(cls)

    def __init__(self, env, seed: int | None = None, *, n_headings: int = 32, speed_fractions=(1.0, 0.5),
                 searches=((3.0, 0.03), (1.5, 0.03), (3.0, 0.06)), max_expansions: int = 100_000, lost_cell: float = 0.005):  # fmt: skip
        super().__init__(env, seed)
        self._env, self.max_steps = simulator_of(env)
        if int(n_headings) != n_headings or n_headings < 4:
            raise ValueError(f"n_headings must be an integer >= 4, got {n_headings!r}")
        self.searches = tuple((float(w), float(c)) for w, c in searches)
        if not self.searches or min(w for w, _ in self.searches) < 1.0 or min(c for _, c in self.searches) <= 0:
            raise ValueError(f"searches must be (weight >= 1, grid > 0) pairs, got {searches!r}")
        if not lost_cell > 0:
            raise ValueError(f"lost_cell must be > 0, got {lost_cell!r}")
        self.moves = heading_moves(int(n_headings), speed_fractions)
        self.max_expansions, self.lost_cell = int(max_expansions), float(lost_cell)
        self.verdict: str | None = None  # of the episode planned last
        self.last_search: dict = {}

    def solve(self) -> dict:
        """Search from the env's current state; returns the memory entries the episode flies."""
        env = self._env
        scenario, world = env.scenario, env.world
        begin = time.perf_counter()
        trajectory, substeps, remaining, reactive, statics, ctg = true_future(env, self.max_steps)
        problem = SpacetimeProblem(trajectory, substeps, scenario.robot_radius, world.radii, np.array(world.robot_xy),
                                   np.array(scenario.goal), scenario.goal_radius, env.arena.box, env.robot_step_length,
                                   statics, ctg)  # fmt: skip
        expansions = 0
        for weight, cell in self.searches:
            result = search(problem, SearchSettings(self.moves, remaining, cell, self.max_expansions, weight))
            outcome, targets = result.outcome, result.targets
            expansions += result.expansions
            if outcome != BUDGET:
                break
        if outcome == FOUND:
            verdict, lost_at = "plan", None
        else:
            lost, lost_at = provably_lost(problem, self.lost_cell)
            verdict = "lost" if lost else "undetermined"
        if reactive:
            verdict = "reactive"
        self.verdict = verdict
        self.last_search = {"verdict": verdict, "steps": len(targets), "expansions": int(expansions),
                            "lost_at_step": lost_at, "seconds": time.perf_counter() - begin}  # fmt: skip
        return {"targets": targets, "next": 0}

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        if np.ndim(observation["robot_position"]) != 1:
            raise ValueError("oracle-clairvoyant reads the simulator of the one env it was made for: it cannot act on a batch")
        return super().predict(observation, state, episode_start, deterministic)

    def plan(self, obs, memory):
        if "targets" not in memory:
            memory.update(self.solve())
        i = memory["next"]
        memory["next"] = i + 1
        targets = memory["targets"]
        self.last_plan = np.vstack([obs["robot_position"], targets[i:]])
        if i < len(targets):
            return targets[i]
        return np.asarray(obs["goal"], np.float64)  # past a failed search's deepest node: head for the goal
