"""Where the limit's own searches leave an episode undetermined, it keeps searching where planners win
(issue 46): ``oracle-clairvoyant`` flies the planners it knows on a copy of the env and, where one arrives
without contact, flies that (verdict "plan"), replayed exactly; episodes it plans or proves lost fly as before."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import agents
import pathplan_env  # noqa: F401
from agents.oracles.clairvoyant import ClairvoyantOracle
from agents.oracles.flown_planners import PLANNERS, fly

#: 30 obstacles at Δd 2 (test split seed 9), and a limit of 8 headings, one speed and 200 nodes a search:
#: its receding scheme is cornered at step 19 and the episode, not provably lost, ends in contact at step 20
SEED, WEAK = 1000000009, {"n_headings": 8, "speed_fractions": (1.0,), "max_expansions": 200, "receding": (20, 10, 0.03, 200, 1)}


def _dense():
    return gym.make("DynamicObstacle-v0", scenario="random", delta_d=2.0, n_obstacles=30)


def _flown(agent, env, seed):
    """The robot's positions after every step of ``agent``'s episode, and the last info."""
    agent.reset()
    obs, _ = env.reset(seed=seed)
    positions, start = [], True
    while True:
        action, _ = agent.predict(obs, None, np.array([start]))
        start = False
        obs, _, terminated, truncated, info = env.step(action)
        positions.append(obs["robot_position"].copy())
        if terminated or truncated:
            return np.array(positions), info


def test_a_cornered_episode_a_planner_wins_is_a_plan():
    env = _dense()
    alone = ClairvoyantOracle(env, seed=SEED, planners=(), **WEAK)
    _, info = _flown(alone, env, SEED)
    assert alone.verdict == "undetermined" and info["collision"]  # cornered, not proved lost: it touched
    oracle = ClairvoyantOracle(env, seed=SEED, **WEAK)
    positions, info = _flown(oracle, env, SEED)
    assert info["is_success"] and not info["collision"]
    assert oracle.verdict == "plan" and oracle.last_search["found_by"] == "astar-spacetime"
    assert oracle.last_search["planners"] == {"astar-spacetime": ("success", len(positions))}  # the first that arrives is flown
    # the flight is the planner's own episode, replayed bit for bit from the copy of the env it flew on
    planner_positions, planner_info = _flown(agents.make("astar-spacetime", env, seed=SEED), env, SEED)
    assert planner_info["is_success"] and np.array_equal(positions, planner_positions)


def test_a_flight_on_a_copy_leaves_the_env_where_it_was():
    env = _dense()
    obs, _ = env.reset(seed=SEED)
    before = env.unwrapped.world.obstacle_state.copy()
    flight = fly("pso-spacetime", env, env.unwrapped, obs, SEED, 5)
    assert len(flight.actions) == 5 and flight.actions.dtype == np.float32 and not flight.collided
    assert env.unwrapped.world.time == 0 and np.array_equal(env.unwrapped.world.obstacle_state, before)
    replayed = [env.step(action)[0]["robot_position"].copy() for action in flight.actions]
    assert np.array_equal(np.array(replayed), flight.positions.astype(np.float32))


def test_episodes_it_plans_or_proves_lost_fly_no_planner():
    for delta_d, seed, verdict in ((4.0, 1000000000, "lost"), (2.0, 1000000000, "plan")):
        env, flights = gym.make("DynamicObstacle-v0", scenario="random", delta_d=delta_d, n_obstacles=30), []
        for planners in (PLANNERS, ()):
            oracle = ClairvoyantOracle(env, seed=seed, planners=planners)
            flights.append(_flown(oracle, env, seed)[0])
            assert oracle.verdict == verdict and oracle.last_search["planners"] == {} and oracle.last_search["flown_by"] is None
        assert np.array_equal(*flights)


def test_the_unicycle_limit_flies_the_unicycle_planners():
    # a unicycle limit of one search of 30 nodes (no receding scheme, no last resort): undetermined, it
    # heads for the goal and collides; astar-unicycle, flown on a copy of the env, arrives
    env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.5, robot="unicycle")
    weak, seed = {"receding": None, "searches": ((3.0, 0.06, 0.1),), "max_expansions": 30, "last_resort": None}, 1000000000
    alone = agents.make("oracle-clairvoyant", env, seed=seed, planners=(), **weak)
    _, info = _flown(alone, env, seed)
    assert alone.verdict == "undetermined" and info["collision"]
    oracle = agents.make("oracle-clairvoyant", env, seed=seed, **weak)
    positions, info = _flown(oracle, env, seed)
    assert info["is_success"] and oracle.verdict == "plan" and oracle.last_search["found_by"] == "astar-unicycle"
    planner_positions, _ = _flown(agents.make("astar-unicycle", env, seed=seed), env, seed)
    assert np.array_equal(positions, planner_positions)
