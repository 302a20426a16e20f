"""The unicycle's physical limit: ``oracle-clairvoyant`` when the env's robot is a unicycle. PRIVILEGED.

It reads the simulator exactly as the holonomic oracle does (:func:`agents.oracles.future.true_future`:
a fresh copy of the episode's world stepped ahead gives every obstacle's true future), and searches
the unicycle's own moves on it (:mod:`agents.planners.unicycle.astar`: (step, x, y, heading, v, ω),
the dynamic window's primitives, each the float32 action the env will receive, flown as the env's
exact arc with the env's arc contact tests, the arena's edges as walls). Its plan replays exactly
(tested): the limit is the unicycle's, with its acceleration and turn-rate limits.

**Lost-episode proof, with headings.** Where no search finds a plan, the holonomic reachable-set
test (:func:`agents.planners.reachable_set.provably_lost`) runs with the unicycle's top speed as
the reach per step. It over-approximates the robot's *positions*: every unicycle state
``(x, y, heading, v, ω)`` reachable after a substep has its ``(x, y)`` within ``max_speed dt / n``
(the arc's length bounds its chord) of a position reachable one substep before, whatever its heading
and velocities (speeds never leave ``[0, max_speed]``). So the set of reachable positions, the
projection of the unicycle's reachable set, lies inside the kept cells at every substep; the arena's
edges, walls to the unicycle, are outside the box the test keeps. When the cells empty, no heading,
speed or turn rate reaches the goal: "lost" is a proof for the unicycle too. The converse is weaker
than for the holonomic robot: a unicycle that cannot turn or brake in time is lost in more episodes
than this test proves, and those stay "undetermined" unless one of the unicycle's planners (``astar-unicycle``,
``pso-unicycle``, ``abc-unicycle``), flown on a copy of the env from the current state
(:mod:`agents.oracles.flown_planners`), arrives without contact: then it flies that planner's actions (verdict
"plan", ``found_by`` its name); where none arrives it flies the one that stays free longest and the
episode stays "undetermined".
"""

from __future__ import annotations

import math
import time

import numpy as np

from agents.base import Agent
from agents.oracles.flown_planners import UNICYCLE_PLANNERS, best_flight
from agents.oracles.future import simulator_of, true_future
from agents.planners.reachable_set import provably_lost
from agents.planners.spacetime.astar import BUDGET, EXHAUSTED, FOUND, HORIZON, SpacetimeProblem
from agents.planners.unicycle.astar import UnicycleProblem, UnicycleResult, search, settings
from agents.planners.unicycle.astar_agent import unicycle_model
from pathplan_env.robots.unicycle import arena_edges


class UnicycleClairvoyantOracle(Agent):
    """Earliest-arrival plan of the unicycle's moves against the obstacles' true future. **Reads the simulator.**

    Built by ``agents.oracles.ClairvoyantOracle(env)`` (``agents.make("oracle-clairvoyant", env)``) when
    ``env``'s robot is a unicycle.

    :param speed_steps, turn_steps: the primitives, fractions of the dynamic window
        (:func:`agents.planners.unicycle.astar.settings`).
    :param receding: the first try, ``(horizon steps, steps committed, merge grid in m, heading bin in rad,
        node budget, retry factor)``: :meth:`receding_plan`, the ``astar-unicycle`` planner's scheme on
        the true future; ``None`` to skip it.
    :param searches: then the successive searches over the whole episode, ``(heuristic weight, merge grid
        in m, heading bin in rad)`` each; a search that fails hands over to the next.
    :param max_expansions: node budget of each search.
    :param last_resort: where all of those fail, one more search over the whole episode, ``(heuristic weight,
        merge grid in m, heading bin in rad, budget factor)``: its budget is ``budget factor × max_expansions``
        (hard episodes need more nodes than the first tries may spend: at Δd 0.5 and 1, 140,000-670,000 on
        the coarse grid); the worst case stays bounded, at about ``(2 × len(searches) + budget factor) ×
        max_expansions`` nodes in all (the receding scheme spends at most what the searches may); ``None``
        to skip it. It runs only where every earlier search failed, so it changes no episode they solve.
        After it the episode is "undetermined" unless the reachable-set test proves it lost.
    :param lost_cell: grid (m) of that test.
    :param planners: registered planners flown on a copy of the env where the episode would stay
        "undetermined" (:mod:`agents.oracles.flown_planners`, as the holonomic oracle does): the first that
        arrives without contact is flown (verdict "plan", ``found_by`` its name), else the one that flies the
        most steps free if that beats the oracle's own flight. Not flown where the obstacles react to the
        robot (the verdict is then "reactive"). ``()`` or ``None``: none.
    """

    def __init__(self, env, seed: int | None = None, *, speed_steps=(-1.0, 0.0, 1.0), turn_steps=(-1.0, -0.5, 0.0, 0.5, 1.0),
                 receding=(20, 10, 0.05, 0.1, 2000, 20), searches=((3.0, 0.03, 0.05), (1.5, 0.03, 0.05), (3.0, 0.06, 0.1)),
                 max_expansions: int = 100_000, last_resort=(3.0, 0.06, 0.1, 10), lost_cell: float = 0.005,
                 planners=UNICYCLE_PLANNERS):  # fmt: skip
        super().__init__(env, seed)
        self._given, self.planners = env, tuple(planners or ())  # (the planners are built for the env given)
        self._env, self.max_steps = simulator_of(env)
        self.model = unicycle_model(env)
        if not lost_cell > 0:
            raise ValueError(f"lost_cell must be > 0, got {lost_cell!r}")
        self.max_expansions, self.lost_cell = int(max_expansions), float(lost_cell)
        self.verdict: str | None = None  # of the episode planned last
        self.last_search: dict = {}
        searches = tuple(tuple(float(v) for v in entry) for entry in searches)
        if not searches or any(len(entry) != 3 for entry in searches):
            raise ValueError(f"searches must be (weight, grid, heading bin) triples, got {searches!r}")
        # checked here, each by name (settings raises ValueError naming the field)
        self.unicycle_searches = tuple(settings(speed_steps, turn_steps, 1, cell, heading_bin, self.max_expansions, weight)
                                       for weight, cell, heading_bin in searches)  # fmt: skip
        self.last_resort = None
        if last_resort is not None:
            if len(last_resort) != 4:
                raise ValueError(f"last_resort must be (weight, grid, heading bin, budget factor) or None, got {last_resort!r}")
            weight, cell, heading_bin, factor = last_resort
            if isinstance(factor, bool) or int(factor) != factor or factor < 1:
                raise ValueError(f"last_resort: its budget factor must be a positive integer, got {factor!r}")
            self.last_resort = settings(speed_steps, turn_steps, 1, cell, heading_bin, self.max_expansions * int(factor), weight)
        self.receding = None
        if receding is not None:
            if len(receding) != 6:
                raise ValueError(f"receding must be (horizon, commit, grid, heading bin, budget, retry factor) or None, got {receding!r}")
            horizon, commit, cell, heading_bin, budget, retry = receding
            if isinstance(commit, bool) or int(commit) != commit or not 1 <= commit <= horizon:
                raise ValueError(f"receding: its steps committed must be an integer in [1, horizon], got {commit!r}")
            if isinstance(retry, bool) or int(retry) != retry or retry < 1:
                raise ValueError(f"receding: its retry factor must be a positive integer, got {retry!r}")
            self.receding = (settings(speed_steps, turn_steps, horizon, cell, heading_bin, budget, 3.0), int(commit), int(retry))

    def receding_plan(self, problem: UnicycleProblem, remaining: int) -> tuple[UnicycleResult, int]:
        """The planner's scheme on the true future: search ``horizon`` steps ahead (a failed search retried
        with ``retry`` times the budget), fly ``commit`` steps of a plan that survives the horizon (one
        step of one that does not: its first step is still free), search again from there, spending at most
        what the whole-episode searches may (``max_expansions`` each). Every step is
        the search's exact move, so the result is a plan of the whole episode, ``FOUND`` if it reaches the goal.

        :return: ``(result, expansions)``: the actions and poses flown, and the nodes expanded."""
        entry, commit, retry = self.receding
        trajectory, n = problem.trajectory, problem.substeps
        actions, poses, step, expansions = [], [problem.start[None]], 0, 0
        outcome = EXHAUSTED
        while step < remaining and expansions < len(self.unicycle_searches) * self.max_expansions:  # at most what the searches spend
            horizon = min(entry.max_steps, remaining - step)
            window = problem._replace(trajectory=trajectory[step * n : (step + horizon) * n + 1], start=poses[-1][-1])
            for budget in (entry.max_expansions, entry.max_expansions * retry):
                result = search(window, entry._replace(max_steps=horizon, max_expansions=budget))
                expansions += result.expansions
                if result.outcome != BUDGET:
                    break
            take = len(result.actions) if result.outcome == FOUND else min(commit if result.outcome == HORIZON else 1, len(result.actions))
            if take == 0:
                break  # every move touches
            actions.append(result.actions[:take])
            poses.append(result.poses[1 : take + 1])
            step += take
            if result.outcome == FOUND:
                outcome = FOUND
                break
        return UnicycleResult(outcome, np.concatenate(actions or [np.zeros((0, 2), np.float32)]), np.concatenate(poses), expansions), expansions

    def solve(self, observation=None) -> dict:
        """Search from the env's current state; returns the memory entries the episode flies.
        ``observation``: the env's current one, which the planners flown where the episode would stay
        "undetermined" start from (none are flown without it)."""
        env = self._env
        scenario, world = env.scenario, env.world
        begin = time.perf_counter()
        trajectory, substeps, remaining, reactive, statics, ctg = true_future(env, self.max_steps)
        start = np.array([*world.robot_xy, world.robot_heading, world.robot_forward_speed, world.robot_angular_velocity], np.float64)
        walls = np.ascontiguousarray(np.vstack([statics, arena_edges(scenario.bounds)]))  # the arena's edges: walls to a unicycle
        problem = UnicycleProblem(trajectory, substeps, scenario.robot_radius, world.radii, start, np.array(scenario.goal),
                                  scenario.goal_radius, self.model, walls, ctg)  # fmt: skip
        expansions, found_by = 0, None
        if self.receding is not None:  # cheap where it works; the searches over the whole episode where it does not
            result, expansions = self.receding_plan(problem, remaining)
            found_by = "receding" if result.outcome == FOUND else None
        stages = [(f"search {i + 1}", entry) for i, entry in enumerate(self.unicycle_searches)]
        stages += [("last resort", self.last_resort)] if self.last_resort is not None else []
        for name, entry in stages if found_by is None else ():
            result = search(problem, entry._replace(max_steps=remaining))  # a failed search hands over: its grid may be why
            expansions += result.expansions
            if result.outcome == FOUND:
                found_by = name
                break
        lost_at = None
        if result.outcome == FOUND:
            verdict = "plan"
        else:  # the module's doc: positions at the unicycle's top speed, every heading and velocity
            reach = self.model.max_speed * self.model.dt
            positions = SpacetimeProblem(trajectory, substeps, scenario.robot_radius, world.radii, start[:2].copy(), problem.goal,
                                         scenario.goal_radius, env.arena.box, reach, statics, ctg)  # fmt: skip
            lost, lost_at = provably_lost(positions, self.lost_cell)
            verdict = "lost" if lost else "undetermined"
        flight, flown, actions, poses = None, {}, result.actions, result.poses
        if verdict == "undetermined" and self.planners and observation is not None and not reactive:  # keep searching where planners win
            flight, flown = best_flight(self.planners, self._given, env, observation, self.seed, remaining, len(result.actions))
            if flight is not None:  # its actions, replayed exactly; its positions as the plan drawn
                actions, poses = flight.actions, np.vstack([start[None, :2], flight.positions])
                verdict, found_by = ("plan", flight.name) if flight.arrived else (verdict, found_by)
        if reactive:
            verdict = "reactive"
        self.verdict = verdict
        self.last_search = {"verdict": verdict, "found_by": found_by, "steps": len(actions), "expansions": int(expansions),
                            "lost_at_step": lost_at, "flown_by": None if flight is None else flight.name, "planners": flown,
                            "seconds": time.perf_counter() - begin}  # fmt: skip
        return {"actions": actions, "poses": poses, "next": 0}

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        if np.ndim(observation["robot_position"]) != 1:
            raise ValueError("oracle-clairvoyant reads the simulator of the one env it was made for: it cannot act on a batch")
        if episode_start is not None and np.any(episode_start) or not self._memory:
            self._memory = [{}]
        memory = self._memory[0]
        begin = time.perf_counter()
        if "actions" not in memory:
            memory.update(self.solve(observation))
        i = memory["next"]
        memory["next"] = i + 1
        self.last_plan = memory["poses"][i:, :2].copy()
        action = memory["actions"][i].copy() if i < len(memory["actions"]) else self.toward_goal(observation)
        self.last_plan_seconds = time.perf_counter() - begin
        return action, state

    def toward_goal(self, observation) -> np.ndarray:
        """Past a failed search's deepest node: turn toward the goal, and drive once roughly facing it."""
        to_goal = np.asarray(observation["goal"], np.float64) - np.asarray(observation["robot_position"], np.float64)
        bearing = math.atan2(to_goal[1], to_goal[0]) - float(observation["robot_heading"][0])
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        turn = max(-1.0, min(1.0, bearing / (self.model.max_turn_rate * self.model.dt)))
        return np.array([1.0 if abs(bearing) < 0.25 * math.pi else -1.0, turn], np.float32)


__all__ = ["UnicycleClairvoyantOracle"]
