"""Planners: they reach the goal, honour SB3's predict contract, and implement the paper's rules."""

import math

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.evaluation import evaluate_policy

import agents
import pathplan_env
from agents.planners.bee_colony import ABCSettings, abc_run
from agents.planners.objective import Scene, evaluate
from agents.planners.pso import inertia_schedule
from pathplan_env import Obstacle, Scenario

# sb3 needs a model path; the unicycle's agents need a unicycle (tests/robots/test_unicycle.py drives them); the learned
# agents are held to what they were trained for (tests/agents/rl/test_ppo.py, test_sarl.py, ...), not static paper cases
LEARNED = ("ppo", "ppo-lidar", "ppo-set", "sarl", "sarl-random", "sarl-crossings", "sb3")
PLANNERS = [name for name in agents.available() if name not in ("straight", *LEARNED, *agents.UNICYCLE_AGENTS)]


def run_episode(agent, env, seed=0):
    return agents.rollout(agent, env, seed)


@pytest.mark.parametrize("case", ["paper-case-1", "paper-case-2", "paper-case-3"])
@pytest.mark.parametrize("name", PLANNERS)
def test_planner_reaches_goal_of_static_paper_case(name, case):
    env = gym.make("DynamicObstacle-v0", scenario=case, delta_d=0)
    info = run_episode(agents.make(name, env, seed=0), env)
    assert info["is_success"] and not info["collision"]


@pytest.mark.parametrize("case", ["paper-case-1", "paper-case-2", "paper-case-3"])
def test_straight_cannot_pass_the_paper_obstacles(case):
    env = gym.make("DynamicObstacle-v0", scenario=case, delta_d=0)
    info = run_episode(agents.make("straight", env), env)
    assert info["collision"]


# privileged oracles read the one env they were made for: they refuse a batch (tests/agents/planners/test_spacetime.py)
ONE_ENV_ONLY = {"oracle-clairvoyant", "oracle-clairvoyant-unicycle", "tracked-oracle-clairvoyant"}
VECTOR_CASES = [(name, "holonomic") for name in [*PLANNERS, "straight", "ppo", "ppo-set", "sarl", "sarl-random", "sarl-crossings"]]
VECTOR_CASES += [(name, "unicycle") for name in sorted(agents.UNICYCLE_AGENTS)]


@pytest.mark.parametrize("name, robot", [case for case in VECTOR_CASES if case[0] not in ONE_ENV_ONLY])
def test_evaluate_policy_runs_every_agent_on_a_two_env_vector_env(name, robot):
    """SB3's evaluate_policy on a 2-env DummyVecEnv, the agent made from the vector env itself: batched
    observations, per-env memory reset by episode_start, the robot read from the env's public facts."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    observation = agents.observation_of(name)
    vec = DummyVecEnv([lambda: gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0.25, robot=robot, observation=observation)] * 2)
    agent = agents.make(name, vec, seed=0)
    assert isinstance(agent, agents.Agent)
    rewards, lengths = evaluate_policy(agent, vec, n_eval_episodes=4, return_episode_rewards=True, warn=False)
    assert len(rewards) == 4 and all(math.isfinite(r) for r in rewards) and min(lengths) >= 1
    assert agent.last_plan_seconds > 0
    # a batch's actions are each env's own: the first env's row equals the action for its observation alone
    obs = vec.reset()
    fresh = agents.make(name, vec, seed=0)
    batch, _ = fresh.predict(obs, deterministic=True)
    single = agents.make(name, vec, seed=0).predict({k: v[0] for k, v in obs.items()}, deterministic=True)[0]
    assert batch.shape == (2, *vec.action_space.shape)
    np.testing.assert_allclose(batch[0], single, rtol=0, atol=1e-6)  # float32 matrix products batch differently


# agents whose act draws no random numbers: on a vector env each env's episodes are those of the agent alone
DETERMINISTIC = [("velocity-obstacle", "holonomic"), ("astar-spacetime", "holonomic"), ("dwa", "unicycle")]


@pytest.mark.parametrize("name, robot", DETERMINISTIC)
def test_evaluate_policy_on_a_vector_env_gives_each_envs_own_episodes(name, robot):
    """What a user relies on when evaluating on a vector env: the returns and lengths are those of
    the agent run alone on each env (its memory reset at each env's episode start, no env's plan
    leaking into the other's), not merely some finite numbers."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    make_env = lambda: gym.make("DynamicObstacle-v0", scenario="paper-case-1", delta_d=0.25, robot=robot)
    vec = DummyVecEnv([make_env] * 2)
    vec.seed(7)  # env i: reset(seed=7 + i), then its episodes follow on without a seed
    rewards, lengths = evaluate_policy(agents.make(name, vec, seed=0), vec, n_eval_episodes=4, return_episode_rewards=True, warn=False)
    alone = []
    for i in range(2):  # evaluate_policy takes two episodes from each env
        env, agent = make_env(), agents.make(name, vec, seed=0)
        seed = 7 + i
        for _ in range(2):
            agent.reset()
            obs, _ = env.reset(seed=seed)
            seed, total, steps, done = None, 0.0, 0, False
            while not done:
                obs, reward, terminated, truncated, _ = env.step(agent.predict(obs, deterministic=True)[0])
                total, steps, done = total + reward, steps + 1, terminated or truncated
            alone.append((steps, total))
    vector = sorted(zip(lengths, rewards))
    assert [n for n, _ in vector] == [n for n, _ in sorted(alone)]
    assert [r for _, r in vector] == pytest.approx([r for _, r in sorted(alone)], rel=1e-5)  # DummyVecEnv keeps rewards as float32


def test_same_seed_same_actions():
    env = gym.make("DynamicObstacle-v0", delta_d=0.5)
    obs, _ = env.reset(seed=4)
    for name in ("pso", "abc", "pso-predictive"):
        a = agents.make(name, env, seed=9).predict(obs)[0]
        b = agents.make(name, env, seed=9).predict(obs)[0]
        np.testing.assert_array_equal(a, b)


def test_unknown_agent_and_bad_override_raise():
    env = gym.make("DynamicObstacle-v0")
    with pytest.raises(ValueError, match="unknown agent"):
        agents.make("a-star", env)
    with pytest.raises(ValueError, match="n_waypoints"):
        agents.make("pso", env, n_waypoints=0)


def test_pso_inertia_follows_eq_7():
    w = inertia_schedule(100, 0.9, 0.4)
    np.testing.assert_allclose(w, 0.9 - (0.9 - 0.4) / 100 * np.arange(100))
    env = gym.make("DynamicObstacle-v0")
    np.testing.assert_array_equal(agents.make("pso", env).inertia, w)
    vanilla = agents.make("pso-vanilla", env).inertia
    assert np.all(vanilla == vanilla[0])  # the ablation keeps a constant inertia


def _one_obstacle_scene():
    return Scene(
        robot=np.array([0.0, 0.0]), goal=np.array([4.0, 0.0]), centers=np.array([[2.0, 0.0]]),
        velocities=np.zeros((1, 2)), radii=np.array([1.0]), speed=1.0, horizon=3.0, penalty_weight=100.0,
    )  # fmt: skip


def test_modified_abc_warm_starts_from_previous_best():
    # Budget of the initial evaluation only: the run returns the best of its starting sources,
    # so the previous best comes back exactly when it seeds the colony.
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-1")
    scene = _one_obstacle_scene()
    previous = np.array([1.0, 1.5, 3.0, 1.5])  # a feasible detour over the obstacle
    modified = agents.make("abc", env, seed=0, population=4, iterations=1)
    assert np.array_equal(modified.optimize(scene, {"best": previous.copy()}), previous)
    vanilla = agents.make("abc-vanilla", env, seed=0, population=4, iterations=1)
    assert not np.array_equal(vanilla.optimize(scene, {"best": previous.copy()}), previous)


def test_modified_abc_scouts_replace_every_infeasible_source():
    # an obstacle covering the whole search box: every source is infeasible in every cycle
    scene = _one_obstacle_scene()._replace(radii=np.array([50.0]))
    sources, cycles = 6, 5
    x0 = np.random.default_rng(0).uniform(-1, 1, size=(sources, 4))
    budget = sources + cycles * 3 * sources
    lo, hi = -np.ones(4), np.ones(4)
    modified = abc_run(x0, lo, hi, ABCSettings(budget, 20, True), 0, scene)
    assert modified.scouted == cycles * sources
    assert len(modified.history) == cycles and modified.history_evaluations[-1] == modified.evaluations == budget
    vanilla = abc_run(x0, lo, hi, ABCSettings(budget, 20, False), 0, scene)
    assert vanilla.scouted < modified.scouted


def test_objective_penalises_cutting_and_predicts_motion():
    scene = _one_obstacle_scene()
    straight = np.array([1.0, 0.0, 3.0, 0.0])
    cost, penalty = evaluate(straight, scene)
    assert penalty[0] > 2 * math.pi and cost[0] == pytest.approx(4.0 + penalty[0])
    # the obstacle moves away fast: the predictive objective sees the straight path clear
    moving = scene._replace(velocities=np.array([[0.0, 10.0]]))
    assert evaluate(straight, moving)[1][0] == 0.0


def test_oracle_length_equals_hand_computed_tangent_path():
    # start and goal 2 m either side of a disc of inflated radius R = 1: tangent, arc, tangent
    path, length = pathplan_env.shortest_path((-2, 0), (2, 0), [(0, 0)], [1.0])
    expected = 2 * math.sqrt(3) + (math.pi - 2 * math.acos(0.5))
    assert length == pytest.approx(expected, rel=1e-9)
    # the oracle flies it in the env (robot radius 0.2 + a fixed margin 0.05 around a 0.75 m obstacle)
    scenario = Scenario(bounds=(-5, -5, 5, 5), start=(-2, 0), goal=(2, 0), obstacles=(Obstacle((0, 0), 0.75),), goal_radius=1e-3)
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=0)
    info = run_episode(agents.make("oracle-static", env, margin=0.05), env)
    assert info["is_success"] and info["path_length"] == pytest.approx(expected, rel=0.01)


@pytest.mark.parametrize("subset", [(1, 2, 3, 4), (0, 1, 3, 4), None])
def test_shortest_path_grows_with_inflation_and_is_clear(subset):
    # Inflating the discs can only lengthen the shortest path. Paper case 3 has many near-coincident
    # tangent points (a regression: zero-length arcs between them were dropped, giving jumps up).
    centers = np.array(pathplan_env.PRESETS["paper-case-3"](None, 0).arrays()["positions"])
    centers = centers if subset is None else centers[list(subset)]
    lengths = []
    for radius in np.arange(0.40, 0.80, 0.005):
        path, length = pathplan_env.shortest_path((0, 0), (5, 5), centers, np.full(len(centers), radius), arc_resolution=0.01)
        lengths.append(length)
        if path is not None:  # the polyline stays out of the discs (up to arc chords) and has the reported length
            gaps = np.linalg.norm(path[:, None] - centers[None], axis=-1) - radius
            assert gaps.min() > -1e-6
            assert np.hypot(*np.diff(path, axis=0).T).sum() == pytest.approx(length, rel=1e-3)
    assert np.all(np.diff(lengths) >= -1e-9), np.round(lengths, 3)


def test_predictive_pso_beats_paper_pso_at_half_radius_per_step():
    episodes = 40
    rates = {}
    for name in ("pso", "pso-predictive"):
        env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0.5)
        agent = agents.make(name, env, seed=0)
        successes = [run_episode(agent, env, seed=1000 + i)["is_success"] for i in range(episodes)]
        rates[name] = np.mean(successes)
    assert rates["pso-predictive"] >= rates["pso"] + 0.3, rates
