"""astar-spacetime's bounded worst case: a work budget per replan, a partial plan free of contact
when it runs out, the escape when nothing is free (issue 22)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.spacetime.anytime import partial_plan
from agents.planners.spacetime.astar import BUDGET, SearchSettings, SearchTree, SpacetimeProblem, replay, search


def dense_problem(seed: int = 3, n_obstacles: int = 30, delta_d: float = 4.0):
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=n_obstacles)
    obs, _ = env.reset(seed=seed)
    agent = agents.make("astar-spacetime", env, seed=0)
    trajectory, n, radii, robot, goal = agent.model.predict_scene(obs)
    segments, ctg = agent.model.statics(obs, {})
    f = agent.facts
    problem = SpacetimeProblem(trajectory, n, f.robot_radius, radii, robot, goal, f.goal_radius, agent.model.arena.box,
                               agent.step_length, segments, ctg)  # fmt: skip
    return problem, agent


def tree(k, h, parent):
    k = np.asarray(k)
    return SearchTree(np.zeros(len(k)), np.zeros(len(k)), k, np.asarray(parent), np.arange(len(k), dtype=float),
                      np.zeros(len(k)), np.asarray(h, float))  # fmt: skip


def test_the_partial_plan_rules_pick_by_survival_then_progress():
    # root 0; a chain 0-1-2-3 (depth 3, 9 steps to go) and a branch 0-4-5 (depth 2, 2 steps to go)
    t = tree(k=[0, 1, 2, 3, 1, 2], h=[10, 10, 9, 9, 5, 2], parent=[-1, 0, 1, 2, 0, 4])
    assert partial_plan(t, "deepest")[:, 0].tolist() == [1, 2, 3]  # the waypoints of nodes 1, 2, 3
    assert partial_plan(t, "progress", min_steps=2)[:, 0].tolist() == [4, 5]  # survives 2 steps, gains ground
    assert partial_plan(t, "progress", min_steps=3)[:, 0].tolist() == [1, 2, 3]  # only the chain survives 3
    assert partial_plan(t, "progress", min_steps=9)[:, 0].tolist() == [1, 2, 3]  # none that long: the deepest's depth
    assert partial_plan(tree([0], [4], [-1]), "progress").shape == (0, 2)  # the root alone: no move is free
    # two searches' trees as one: the second's chain 0-1-2 (waypoints 1, 2) gets nearer than anything in the first
    assert partial_plan([t, tree(k=[0, 1, 2], h=[10, 3, 1], parent=[-1, 0, 1])], "progress", min_steps=2)[:, 0].tolist() == [1, 2]
    assert partial_plan([t, tree(k=[0, 1, 2], h=[10, 3, 1], parent=[-1, 0, 1])], "deepest")[:, 0].tolist() == [1, 2, 3]
    with pytest.raises(ValueError, match="rule"):
        partial_plan(t, "best")


def test_a_search_stops_at_its_work_budget_and_its_partial_plan_is_free_of_contact():
    problem, agent = dense_problem()
    settings = SearchSettings(agent.moves, agent.horizon_steps, agent.cell, 1500, agent.h_weight)
    full = search(problem, settings)
    budget = full.work // 4
    cut = search(problem, settings._replace(max_work=float(budget)))
    assert cut.outcome == BUDGET and cut.expansions < full.expansions
    n_moves, n, obstacles = len(agent.moves) + 2, problem.substeps, len(problem.radii)
    assert budget <= cut.work <= budget + obstacles + n_moves * obstacles * (1 + n)  # at most one expansion past it
    for rule in ("deepest", "progress"):
        targets = partial_plan(cut.tree, rule)
        assert len(targets) >= 1
        assert replay(problem, targets) == (len(targets), False)  # every step free on the prediction
    # the same search run longer is the same search: its first nodes are the cut one's
    assert np.array_equal(full.tree.x[: len(cut.tree.x)], cut.tree.x)


def test_the_budgeted_planner_is_deterministic_and_bounded():
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=4.0, n_obstacles=30)
    runs = []
    for _ in range(2):
        agent = agents.make("astar-spacetime", env, seed=0, max_work=50_000)
        obs, _ = env.reset(seed=5)
        actions, work = [], []
        for _ in range(15):
            action, _ = agent.predict(obs, deterministic=True)
            actions.append(action)
            work.append(agent.last_search.get("work", 0))
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        runs.append(np.array(actions))
        assert max(work) < 50_000 + 66 * 31 * 40  # within one expansion of the budget
    assert np.array_equal(runs[0], runs[1])


@pytest.mark.parametrize(
    "kwargs, name",
    [({"max_work": 0}, "max_work"), ({"time_budget_ms": -1.0}, "time_budget_ms"), ({"time_budget_ms": float("nan")}, "time_budget_ms"),
     ({"partial": "best"}, "partial"), ({"partial_min_steps": 0}, "partial_min_steps"), ({"max_expansions": 0}, "max_expansions")],
)  # fmt: skip
def test_bad_budget_arguments_raise_naming_them(kwargs, name):
    env = gym.make("DynamicObstacle-v0", scenario="random")
    with pytest.raises(ValueError, match=name):
        agents.make("astar-spacetime", env, **kwargs)


def test_a_wall_clock_budget_shrinks_the_work_budget_after_a_first_search():
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=4.0, n_obstacles=30)
    agent = agents.make("astar-spacetime", env, seed=0, time_budget_ms=1.0)
    assert agent.work_budget() == agent.max_work  # no rate measured yet
    obs, _ = env.reset(seed=5)
    agent.predict(obs, deterministic=True)
    assert agent.work_budget() < agent.max_work  # ~1 ms of work at the measured rate
