"""The space-time PSO and ABC in dense scenes: the constraint rules, the early exit, determinism."""

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.bee_colony import ABCSettings, abc_run
from agents.planners.constraints import ADAPTIVE, DEB, PENALTY, ConstraintRule, better, constraint_rule
from agents.planners.objective import Scene
from agents.planners.pso import PSOSettings, inertia_schedule, pso_run
from pathplan_env import Scenario
from pathplan_env.scenarios.scenario import Obstacle
from pathplan_env.scenarios.splits import heldout_seeds


def _scene(radius: float) -> Scene:
    """One disc of ``radius`` on the straight line from (0, 0) to (4, 0)."""
    return Scene(robot=np.array([0.0, 0.0]), goal=np.array([4.0, 0.0]), centers=np.array([[2.0, 0.0]]),
                 velocities=np.zeros((1, 2)), radii=np.array([radius]), speed=1.0, horizon=3.0, penalty_weight=100.0)  # fmt: skip


def test_deb_ranks_a_feasible_dearer_plan_before_an_infeasible_cheaper_one():
    feasible, infeasible = (9.0, 0.0), (5.0, 2.0)  # (cost, penalty)
    assert better(*feasible, *infeasible, DEB, 1.0) and not better(*infeasible, *feasible, DEB, 1.0)
    assert not better(*feasible, *infeasible, PENALTY, 1.0)  # the plain penalty takes the cheaper one
    assert better(5.0, 1.0, 4.0, 2.0, DEB, 1.0)  # between infeasible ones: the smaller violation
    assert better(3.0, 0.0, 4.0, 0.0, DEB, 1.0) and not better(4.0, 0.0, 3.0, 0.0, DEB, 1.0)
    assert better(*feasible, *infeasible, ADAPTIVE, 4.0) and not better(*feasible, *infeasible, ADAPTIVE, 1.0)


@pytest.mark.parametrize("optimizer", ["pso", "abc"])
def test_deb_run_returns_a_feasible_plan(optimizer):
    scene = _scene(1.0)
    lo, hi = np.full(4, -3.0), np.full(4, 5.0)
    x0 = np.random.default_rng(0).uniform(lo, hi, size=(20, 4))
    x0[0] = [1.0, 0.0, 3.0, 0.0]  # the straight line through the disc: cheap once, infeasible
    rule = constraint_rule("deb")
    if optimizer == "pso":
        result = pso_run(x0, lo, hi, PSOSettings(inertia_schedule(40, 0.9, 0.4), 1.5, 1.5, 0.2, rule), 0, scene)
    else:
        result = abc_run(x0[:10], lo, hi, ABCSettings(800, 20, True, rule), 0, scene)
    assert result.best_penalty == 0.0 and result.best_cost > 4.0


@pytest.mark.parametrize("field, kwargs", [("constraint", {"constraint": "static"}), ("stall", {"stall": -1}),
                                           ("violation", {"violation": "depth"}), ("constraint", {"constraint": None}),
                                           ("search_expansions", {"search_expansions": -1}), ("dense_budget", {"dense_budget": -2.0})])  # fmt: skip
@pytest.mark.parametrize("name", ["pso-spacetime", "abc-spacetime"])
def test_bad_options_raise_naming_the_field(name, field, kwargs):
    env = gym.make("DynamicObstacle-v0")
    with pytest.raises(ValueError, match=field):
        agents.make(name, env, **kwargs)
    with pytest.raises(ValueError, match="adaptive"):
        constraint_rule("adaptive", grow=0.5)


def _unchanged_runs(history: np.ndarray, tolerance: float) -> list[int]:
    """The early exit's count after each iteration of a feasible run's history."""
    runs, count = [], 0
    for before, after in zip(np.concatenate([[np.inf], history[:-1]]), history):
        count = count + 1 if before - after <= tolerance else 0
        runs.append(count)
    return runs


@pytest.mark.parametrize("optimizer", ["pso", "abc"])
def test_early_exit_stops_once_stable_and_not_before(optimizer):
    scene = _scene(0.5)
    lo, hi = np.full(4, -3.0), np.full(4, 5.0)
    x0 = np.random.default_rng(1).uniform(lo, hi, size=(20, 4))
    stall = 4

    def run(rule):
        if optimizer == "pso":
            return pso_run(x0, lo, hi, PSOSettings(inertia_schedule(200, 0.9, 0.4), 1.5, 1.5, 0.2, rule), 0, scene)
        return abc_run(x0[:10], lo, hi, ABCSettings(4000, 20, True, rule), 0, scene)

    full, early = run(ConstraintRule()), run(constraint_rule("penalty", stall))
    assert early.best_penalty == 0.0 and len(early.history) < len(full.history)
    # the same run up to the exit (same random stream), stopped the first time the count reached ``stall``
    assert np.array_equal(early.history, full.history[: len(early.history)])
    runs = _unchanged_runs(early.history, ConstraintRule().tolerance)
    assert runs[-1] == stall and max(runs[:-1], default=0) < stall
    # an infeasible best never stops early: an obstacle covering the whole box
    blocked = _scene(50.0)
    if optimizer == "pso":
        stuck = pso_run(x0, lo, hi, PSOSettings(inertia_schedule(30, 0.9, 0.4), 1.5, 1.5, 0.2, constraint_rule("deb", 2)), 0, blocked)
        assert len(stuck.history) == 30
    else:
        stuck = abc_run(x0[:10], lo, hi, ABCSettings(600, 20, True, constraint_rule("deb", 2)), 0, blocked)
        assert stuck.evaluations > 600 - 3 * 10  # ran until the budget was spent (a cycle costs at most 3 SN)


@pytest.mark.parametrize("name", ["pso-spacetime", "abc-spacetime"])
@pytest.mark.parametrize("options", [{"constraint": "deb", "violation": "first-contact", "stall": 3},
                                     {"constraint": "adaptive", "violation": "first-contact"}])  # fmt: skip
def test_same_seed_same_actions_in_a_dense_fast_scene(name, options):
    env = gym.make("DynamicObstacle-v0", scenario="random", n_obstacles=30, delta_d=2.0)
    runs = []
    for _ in range(2):
        agent = agents.make(name, env, seed=3, **options)
        obs, _ = env.reset(seed=heldout_seeds(6, 1)[0])
        actions = []
        for _ in range(8):
            action, _ = agent.predict(obs, deterministic=True)
            actions.append(action)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        runs.append(np.array(actions))
    assert np.array_equal(runs[0], runs[1])


#: A wall of 12 touching resting discs between start and goal (issue 21's scene): the way bends.
WALL_OF_DISCS = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 1),
                         obstacles=tuple(Obstacle(center=(3.0, 0.3 + 0.601 * i), radius=0.3) for i in range(12)))  # fmt: skip
#: Resting discs off the straight line, and one disc moving far from it: the way does not bend.
DISCS_ASIDE = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 1),
                       obstacles=tuple(Obstacle(center=(2.0 + 1.5 * i, 6.0), radius=0.4) for i in range(4))
                       + (Obstacle(center=(5.0, 9.0), radius=0.3, velocity=(0.5, 0.0)),))  # fmt: skip
#: The same resting discs alone: nothing moves.
DISCS_ASIDE_AT_REST = Scenario(bounds=(0, 0, 10, 10), start=(1, 1), goal=(9, 1), obstacles=DISCS_ASIDE.obstacles[:4])


def _replan_evaluations(name, seed=None, **make_kwargs):
    env = gym.make("DynamicObstacle-v0", **make_kwargs)
    agent = agents.make(name, env, seed=0)
    obs, _ = env.reset(seed=seed)
    spent = []
    for _ in range(6):
        action, _ = agent.predict(obs, deterministic=True)
        spent.append(int(agent.last_history_evaluations[-1]))
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    return spent, agent.population * agent.iterations, agent.population


@pytest.mark.parametrize("name", ["pso-spacetime", "abc-spacetime"])
def test_no_early_exit_where_the_way_bends_or_nothing_moves(name):
    """Behind a wall of resting discs, and where nothing moves, every replan spends the whole budget;
    with resting discs off the way and a disc moving, and among moving discs, the default early exit
    stops replans short (docs/results/walls_stall)."""
    behind, budget, population = _replan_evaluations(name, scenario=WALL_OF_DISCS, delta_d=None)
    assert min(behind) >= budget - population  # the whole budget (ABC's last cycle may stop inside it)
    at_rest, *_ = _replan_evaluations(name, scenario=DISCS_ASIDE_AT_REST, delta_d=None)
    assert min(at_rest) >= budget - population
    aside, *_ = _replan_evaluations(name, scenario=DISCS_ASIDE, delta_d=None)
    assert min(aside) < budget // 2
    moving, *_ = _replan_evaluations(name, seed=heldout_seeds(6, 1)[0], scenario="random", delta_d=0.5)
    assert min(moving) < budget // 2
