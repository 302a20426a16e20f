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

Where every search spends its budget and the episode is not provably lost, it does not guess: it
ends the episode as the best planner it knows would, ``astar-spacetime``'s receding scheme flown on
the true future (:meth:`ClairvoyantOracle.receding_plan`). Each step of that is a search's exact
move, free of contact, so it never collides while the scheme finds a free move (until the episode
ends); the verdict is "plan" if it reaches the goal (its moves prove a collision-free arrival), else
"undetermined": nothing proved success or impossibility. Where it is cornered (no move free, the
search exhausted up to its grid) the reachable-set test runs again on a grid twice as fine, then
where asked (``straight_lost``) the proof that models the env's one straight move a step
(:mod:`agents.planners.straight_lost`), and "lost" if either proves it.

Where the episode would still stay "undetermined" (cornered and not proved lost, or the scheme's moves
run to the episode's end short of the goal), it keeps searching where planners win: it flies the
planners it knows (``astar-spacetime``, ``pso-spacetime``, ``abc-spacetime``, default settings, the
episode's seed) on a copy of the env from its current state (:mod:`agents.oracles.flown_planners`; a
copied env continues the episode bit for bit) and flies the first that arrives without contact, its
actions replayed exactly: the verdict is "plan", ``found_by`` the planner's name. Else it stays
"undetermined" and flies whichever stays free longest: the scheme's moves, the last search's deepest
node, or a planner's flight (``last_search["flown_by"]``); cornered, that still ends in contact where
every one of them does. ``last_search["planners"]`` gives each flight's outcome and steps.

Where goal-directed obstacles see the robot (``Scenario.robot_visible``), their future depends on
what the robot does and no fixed trajectory bounds it: the oracle then plans against the future
they would have without the robot, says so (verdict ``"reactive"``) and gives no limit.
"""

from __future__ import annotations

import time

import numpy as np

from agents.base import Agent
from agents.oracles.clairvoyant_unicycle import UnicycleClairvoyantOracle
from agents.oracles.flown_planners import PLANNERS, best_flight
from agents.oracles.future import simulator_of, true_future
from agents.planners.reachable_set import provably_lost
from agents.planners.spacetime.astar import BUDGET, EXHAUSTED, FOUND, HORIZON, SearchSettings, SpacetimeProblem, heading_moves, search
from agents.planners.straight_lost import provably_lost_straight
from pathplan_env.robots.holonomic import robot_move
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
        "undetermined" unless the reachable-set test proves it lost or ``receding`` reaches the goal.
    :param lost_cell: grid (m) of that reachable-set test (half of it where ``receding`` is cornered).
    :param receding: where every search failed and the episode is not provably lost, how it is ended:
        ``(horizon steps, steps committed, merge grid in m, node budget, retry factor)`` of
        :meth:`receding_plan`; ``None``: fly the last search's deepest node, then head for the goal
        (0.1.0's way, which may collide).
    :param straight_lost: where ``receding`` is cornered and the finer reachable set proves nothing, the
        lost proof of the robot's one straight move a step (:mod:`agents.planners.straight_lost`):
        ``(grid in m, steps)``, e.g. ``(0.005, 4)``; ``None`` (the default): none, since at grids that run
        in minutes it proved none of the traced cornered episodes lost. Holonomic robot only (the
        unicycle's oracle keeps the reachable set). It sets only the verdict: the episode flies as without it.
    :param planners: registered planners flown, each with its default settings and the episode's seed,
        on a copy of the env from the current state where the episode would stay "undetermined"
        (:mod:`agents.oracles.flown_planners`): the first that arrives without contact is flown (verdict
        "plan", ``found_by`` its name), else the one that flies the most steps free if that beats the
        oracle's own flight. ``()`` or ``None``: none. Not flown where the obstacles react to the robot
        (verdict "reactive": no limit is given there).
    """

    def __new__(cls, *args, **kwargs):
        # the limit searches the env's own robot's moves: a unicycle's env gets the unicycle's oracle,
        # built whole here (one name, ``oracle-clairvoyant``, is the harness's limit for every robot)
        env = args[0] if args else kwargs.get("env")
        if cls is ClairvoyantOracle and isinstance(getattr(getattr(env, "unwrapped", None), "action_type", None), UnicycleAction):
            return UnicycleClairvoyantOracle(*args, **kwargs)
        return super().__new__(cls)

    def __init__(self, env, seed: int | None = None, *, n_headings: int = 32, speed_fractions=(1.0, 0.5),
                 searches=((3.0, 0.03), (1.5, 0.03), (3.0, 0.06)), max_expansions: int = 100_000, lost_cell: float = 0.005,
                 receding=(20, 10, 0.03, 2000, 10), straight_lost=None, planners=PLANNERS):  # fmt: skip
        super().__init__(env, seed)
        self._given = env  # what the planners it flies are built for (:mod:`agents.oracles.flown_planners`)
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
        self.receding = None if receding is None else _receding_settings(receding)
        if straight_lost is not None and (len(straight_lost) != 2 or not straight_lost[0] > 0 or not _whole(straight_lost[1])):
            raise ValueError(f"straight_lost must be (grid > 0 in m, steps >= 1) or None, got {straight_lost!r}")
        self.straight_lost = None if straight_lost is None else (float(straight_lost[0]), int(straight_lost[1]))
        self.planners = tuple(planners or ())
        self.verdict: str | None = None  # of the episode planned last
        self.last_search: dict = {}

    def receding_plan(self, problem: SpacetimeProblem, remaining: int) -> tuple[int, np.ndarray, int]:
        """``astar-spacetime``'s scheme on the true future, from ``problem.start`` to the goal or the
        episode's end: search ``horizon`` steps ahead (the oracle's first (weight, grid), a search that
        spends its budget retried with ``retry`` times it), fly ``commit`` steps of a plan that reaches
        the horizon, or of the deepest node of one that spent its budget while ``commit`` more of its
        steps stay free beyond them, else one step (still free), and search again from there. Every
        step is a search's exact move, so the waypoints replay exactly and touch nothing; they stop
        short of the episode's end only where no move is free. Bounded: the retries stop once it has
        spent what the whole-episode searches may (``max_expansions`` each), so at most that plus one
        ``budget`` a step.

        :return: ``(outcome, targets, expansions)``: ``FOUND`` if the waypoints reach the goal,
            ``EXHAUSTED`` if they stop where no move is free, else ``HORIZON``."""
        horizon_steps, commit, cell, budget, retry = self.receding
        trajectory, n = problem.trajectory, problem.substeps
        weight, allowance = self.searches[0][0], len(self.searches) * self.max_expansions
        parts, position, step, expansions, outcome = [], problem.start, 0, 0, HORIZON
        while step < remaining:
            horizon = min(horizon_steps, remaining - step)
            window = problem._replace(trajectory=trajectory[step * n : (step + horizon) * n + 1], start=position)
            for nodes in (budget, budget * retry) if expansions < allowance else (budget,):
                result = search(window, SearchSettings(self.moves, horizon, cell, nodes, weight))
                expansions += result.expansions
                if result.outcome != BUDGET:
                    break
            targets = result.targets
            if result.outcome in (FOUND, HORIZON):
                take = len(targets) if result.outcome == FOUND else min(commit, len(targets))
            else:  # BUDGET: a deep node's path is safe to commit to; EXHAUSTED: every path ends in contact, go step by step
                take = min(commit, len(targets) - commit) if result.outcome == BUDGET else 0
                take = max(take, min(1, len(targets)))
            if take == 0:
                outcome = EXHAUSTED  # every move touches
                break
            parts.append(targets[:take])
            position = _flown_to(self._env.arena, position, targets[:take], problem.reach)
            step += take
            if result.outcome == FOUND:
                outcome = FOUND
                break
        return outcome, np.concatenate(parts or [np.zeros((0, 2))]), expansions

    def problem(self) -> tuple[SpacetimeProblem, int, bool]:
        """``(problem, remaining steps, reactive)``: the env's current state and its true future, as
        :meth:`solve` searches it (``scripts``-side checks of a verdict read the same problem)."""
        env = self._env
        scenario, world = env.scenario, env.world
        trajectory, substeps, remaining, reactive, statics, ctg = true_future(env, self.max_steps)
        problem = SpacetimeProblem(trajectory, substeps, scenario.robot_radius, world.radii, np.array(world.robot_xy),
                                   np.array(scenario.goal), scenario.goal_radius, env.arena.box, env.robot_step_length,
                                   statics, ctg)  # fmt: skip
        return problem, remaining, reactive

    def solve(self, observation=None) -> dict:
        """Search from the env's current state; returns the memory entries the episode flies.
        ``observation``: the env's current one, which the planners flown where the episode would stay
        "undetermined" start from (none are flown without it)."""
        begin = time.perf_counter()
        problem, remaining, reactive = self.problem()
        expansions = 0
        for weight, cell in self.searches:
            result = search(problem, SearchSettings(self.moves, remaining, cell, self.max_expansions, weight))
            outcome, targets = result.outcome, result.targets
            expansions += result.expansions
            if outcome != BUDGET:
                break
        found_by = "search" if outcome == FOUND else None
        if outcome == FOUND:
            verdict, lost_at = "plan", None
        else:
            lost, lost_at = provably_lost(problem, self.lost_cell)
            verdict = "lost" if lost else "undetermined"
            if verdict == "undetermined" and self.receding is not None:  # end it as the best planner would, touching nothing
                outcome, flown, spent = self.receding_plan(problem, remaining)
                expansions += spent
                if outcome == FOUND or len(flown) >= len(targets):  # else the last search's deepest node stays free longer
                    targets = flown
                if outcome == FOUND:
                    verdict, found_by = "plan", "receding"
                elif outcome == EXHAUSTED:  # cornered where no move is free: a finer reachable set may prove it
                    lost, lost_at = provably_lost(problem, self.lost_cell / 2)
                    if not lost and self.straight_lost is not None:  # the env's one straight move a step: tighter
                        cell, steps = self.straight_lost
                        straight, at = provably_lost_straight(problem, cell, cell, steps)
                        lost, lost_at = (True, at) if straight else (lost, lost_at)
                    verdict = "lost" if lost else verdict
        flight, flown = None, {}
        if verdict == "undetermined" and self.planners and observation is not None and not reactive:  # keep searching where planners win
            flight, flown = best_flight(self.planners, self._given, self._env, observation, self.seed, remaining, len(targets))
            if flight is not None and flight.arrived:
                verdict, found_by = "plan", flight.name
        if reactive:
            verdict = "reactive"
        self.verdict = verdict
        steps = len(targets if flight is None else flight.actions)
        self.last_search = {"verdict": verdict, "found_by": found_by, "steps": steps, "expansions": int(expansions), "lost_at_step": lost_at,
                            "flown_by": None if flight is None else flight.name, "planners": flown,
                            "seconds": time.perf_counter() - begin}  # fmt: skip
        return {"targets": targets, "next": 0, "flight": flight}

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = False):
        if np.ndim(observation["robot_position"]) != 1:
            raise ValueError("oracle-clairvoyant reads the simulator of the one env it was made for: it cannot act on a batch")
        return super().predict(observation, state, episode_start, deterministic)

    def act(self, obs, memory):
        if "targets" not in memory:
            memory.update(self.solve(obs))
        flight = memory["flight"]
        if flight is None:
            return super().act(obs, memory)
        i = memory["next"]  # a planner's flight on a copy of the env: its actions, replayed exactly
        memory["next"] = i + 1
        self.last_plan = np.vstack([obs["robot_position"], flight.positions[i:]])
        if i < len(flight.actions):
            return flight.actions[i]
        return self.waypoint_to_action(np.asarray(obs["goal"], np.float64))  # past its end (a timeout): head for the goal

    def plan(self, obs, memory):
        if "targets" not in memory:
            memory.update(self.solve(obs))
        i = memory["next"]
        memory["next"] = i + 1
        targets = memory["targets"]
        self.last_plan = np.vstack([obs["robot_position"], targets[i:]])
        if i < len(targets):
            return targets[i]
        return np.asarray(obs["goal"], np.float64)  # past a failed search's deepest node: head for the goal


def _whole(value) -> bool:
    """Whether ``value`` is a positive whole number (not a bool)."""
    return not isinstance(value, bool) and int(value) == value and value >= 1


def _receding_settings(receding) -> tuple[int, int, float, int, int]:
    """``receding`` checked: (horizon, commit, grid, budget, retry).

    :raises ValueError: naming ``receding`` and the entry that is wrong."""
    if len(receding) != 5:
        raise ValueError(f"receding must be (horizon, commit, grid, budget, retry factor) or None, got {receding!r}")
    horizon, commit, cell, budget, retry = receding
    for name, value in (("horizon", horizon), ("steps committed", commit), ("budget", budget), ("retry factor", retry)):
        if isinstance(value, bool) or int(value) != value or value < 1:
            raise ValueError(f"receding: its {name} must be a positive integer, got {value!r}")
    if commit > horizon:
        raise ValueError(f"receding: its steps committed must be at most its horizon {horizon}, got {commit!r}")
    if not cell > 0:
        raise ValueError(f"receding: its grid must be > 0, got {cell!r}")
    return int(horizon), int(commit), float(cell), int(budget), int(retry)


def _flown_to(arena, start: np.ndarray, targets: np.ndarray, reach: float) -> np.ndarray:
    """Where the robot is after flying ``targets`` from ``start``, to the bit as the env and the
    search move it (the float32 action, then ``robot_move``): the next window starts there."""
    x, y = float(start[0]), float(start[1])
    for action in arena.waypoint_to_action(targets):
        _, _, _, dx, dy = robot_move(action, arena.box, x, y, reach)
        x, y = x + dx, y + dy
    return np.array([x, y])
