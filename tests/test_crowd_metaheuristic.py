"""The paper's space-time optimisers among crowds that steer (maze-crowd): past the horizon a wall scene's
rest of the path may pay nothing on the obstacles its straight pieces pass; the crowd variants ``pso-crowd`` /
``abc-crowd`` (a wider margin) and the cone prediction act."""

import math

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.costtogo import STRAIGHT_LINE, cost_to_go
from agents.planners.objective import FIRST_CONTACT, INFEASIBLE, TimedScene, timed_path_cost

PLANNERS = ("pso-spacetime", "abc-spacetime", "pso-crowd", "abc-crowd")


def _scene(field, rest_obstacles: bool) -> TimedScene:
    """A robot at (1, 1) bound for (9, 1), one disc at rest at (6, 1) on the straight line past a
    2-step horizon, and ``field`` as the cost-to-go."""
    steps, substeps = 2, 1
    trajectory = np.zeros((steps * substeps + 1, 1, 4))
    trajectory[:, 0, :2] = 6.0, 1.0
    return TimedScene(trajectory, substeps, 0.2, np.array([0.3]), np.array([1.0, 1.0]), np.array([9.0, 1.0]), 0.1, 0.25, steps,
                      100.0, np.zeros((steps, 1)), np.zeros((0, 5)), field, FIRST_CONTACT, INFEASIBLE, rest_obstacles)  # fmt: skip


def test_rest_obstacles_off_leaves_the_rest_past_the_horizon_unpaid_on_obstacles_where_there_are_walls():
    """The rest's straight piece through the disc pays Eq. 4 (its circumference and 100 per metre of depth)
    without walls, and with a cost-to-go field unless ``rest_obstacles=False`` (pso-crowd, abc-crowd): then
    the pieces, which may cut walls, pay nothing on the discs they pass."""
    env = gym.make("DynamicObstacle-v0", scenario="maze")
    box = agents.make("pso-spacetime", env, 0).facts.arena.box
    far_wall = np.array([[1.0, 8.0, 2.0, 8.0, 0.05]])  # a field that does not bend the way from (1, 1) to (9, 1)
    field = cost_to_go(np.array([9.0, 1.0]), 0.1, box, far_wall, 0.2)
    x = np.array([3.0, 1.0, 8.0, 1.0, 1.0, 1.0, 1.0])  # along the line at top speed: past the horizon through the disc
    costs = {(name, rest): timed_path_cost(x, _scene(f, rest)) for name, f in (("open", STRAIGHT_LINE), ("walls", field)) for rest in (True, False)}
    eq4 = 2 * math.pi * (0.3 + 0.2) + 100.0 * (0.3 + 0.2)  # the disc's circumference and the full depth
    assert all(penalty == 0.0 for _, penalty in costs.values())  # a contact past the horizon is no constraint
    assert costs[("open", True)] == costs[("open", False)]  # without walls the option changes nothing
    assert costs[("walls", True)][0] == pytest.approx(costs[("open", True)][0], abs=0.3)  # the field's grid error
    assert costs[("walls", True)][0] - costs[("walls", False)][0] == pytest.approx(eq4)


@pytest.mark.parametrize("name", ["pso-crowd", "abc-crowd"])
def test_registry_makes_the_crowd_variants_with_a_wider_margin(name):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    agent, plain = agents.make(name, env, 0), agents.make(name.replace("crowd", "spacetime"), env, 0)
    assert agent.model.margin == 0.05 > plain.model.margin and agent.model.prediction == plain.model.prediction == "physics"
    assert agent.timed_problem(env.reset(seed=0)[0]).rest_obstacles is False and plain.rest_obstacles is True
    assert agent.optimizer == plain.optimizer == name.split("-")[0] and agent.population == plain.population


@pytest.mark.slow  # one maze-crowd episode of ~100 replans and one of 38: ~40 s on a quiet machine
def test_pso_spacetime_gets_past_the_humans_where_the_rest_past_its_horizon_held_it():
    """maze-crowd validation episode 11 at Δd 0.5: with Eq. 4 charged on the humans the rest's straight
    pieces pass (through walls) the robot stays behind a human until one walks into it (step 38); with
    ``rest_obstacles=False`` it reaches the goal."""
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=0.5)
    charged = agents.rollout(agents.make("pso-spacetime", env, seed=900000011), env, 900000011)
    assert charged["collision"]
    unpaid = agents.rollout(agents.make("pso-spacetime", env, seed=900000011, rest_obstacles=False), env, 900000011)
    assert unpaid["is_success"]


@pytest.mark.parametrize("name", PLANNERS)
def test_the_cone_prediction_acts_in_a_maze_crowd_episode(name):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=0.5)
    obs, _ = env.reset(seed=3)
    agent = agents.make(name, env, 3, prediction="cone", cone_degrees=30.0, margin=0.1)
    assert agent.model.prediction == "cone" and agent.model.cone == pytest.approx(np.radians(30.0))
    start = obs["robot_position"].copy()
    for t in range(5):
        action, _ = agent.predict(obs, episode_start=np.array([t == 0]))
        assert env.action_space.contains(np.asarray(action, env.action_space.dtype))
        obs, _, terminated, truncated, _ = env.step(action)
        assert not (terminated or truncated)
    assert np.hypot(*(obs["robot_position"] - start)) > 0.1  # it moved


@pytest.mark.parametrize("field, kwargs", [("margin", {"margin": 1.5}), ("prediction", {"prediction": "psychic"}),
                                           ("cone_degrees", {"cone_degrees": 95.0}), ("rest_obstacles", {"rest_obstacles": "no"})])  # fmt: skip
@pytest.mark.parametrize("name", PLANNERS)
def test_bad_options_raise_naming_the_field(name, field, kwargs):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    with pytest.raises(ValueError, match=field):
        agents.make(name, env, **kwargs)
