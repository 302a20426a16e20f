"""The paper's space-time optimisers among crowds that steer (maze-crowd): past the horizon a wall scene's
rest of the path pays nothing on the obstacles its straight pieces pass; the crowd variants ``pso-crowd`` /
``abc-crowd`` (a wider margin) and the cone prediction act."""

import math

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.costtogo import STRAIGHT_LINE, cost_to_go
from agents.planners.objective import FIRST_CONTACT, TimedScene, timed_path_cost

PLANNERS = ("pso-spacetime", "abc-spacetime", "pso-crowd", "abc-crowd")


def _scene(field) -> TimedScene:
    """A robot at (1, 1) bound for (9, 1), one disc at rest at (6, 1) on the straight line past a
    2-step horizon, and ``field`` as the cost-to-go."""
    steps, substeps = 2, 1
    trajectory = np.zeros((steps * substeps + 1, 1, 4))
    trajectory[:, 0, :2] = 6.0, 1.0
    return TimedScene(trajectory, substeps, 0.2, np.array([0.3]), np.array([1.0, 1.0]), np.array([9.0, 1.0]), 0.1, 0.25, steps,
                      100.0, np.zeros((steps, 1)), np.zeros((0, 5)), field, FIRST_CONTACT)  # fmt: skip


def test_the_rest_past_the_horizon_pays_eq4_on_obstacles_only_without_a_cost_to_go():
    """Without walls the rest's straight piece through the disc pays Eq. 4 (its circumference and 100 per
    metre of depth); with a cost-to-go field its straight pieces may cut walls, so they pay nothing on
    the discs they pass (they held pso-spacetime still behind humans in maze-crowd)."""
    env = gym.make("DynamicObstacle-v0", scenario="maze")
    box = agents.make("pso-spacetime", env, 0).facts.arena.box
    far_wall = np.array([[1.0, 8.0, 2.0, 8.0, 0.05]])  # a field that does not bend the way from (1, 1) to (9, 1)
    field = cost_to_go(np.array([9.0, 1.0]), 0.1, box, far_wall, 0.2)
    x = np.array([3.0, 1.0, 8.0, 1.0, 1.0, 1.0, 1.0])  # along the line at top speed: past the horizon through the disc
    open_cost, open_penalty = timed_path_cost(x, _scene(STRAIGHT_LINE))
    wall_cost, wall_penalty = timed_path_cost(x, _scene(field))
    eq4 = 2 * math.pi * (0.3 + 0.2) + 100.0 * (0.3 + 0.2)  # the disc's circumference and the full depth
    assert open_penalty == wall_penalty == 0.0  # a contact past the horizon is no constraint
    assert open_cost - wall_cost == pytest.approx(eq4, abs=0.3)  # the field's grid error on the rest's length


@pytest.mark.parametrize("name", ["pso-crowd", "abc-crowd"])
def test_registry_makes_the_crowd_variants_with_a_wider_margin(name):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    agent, plain = agents.make(name, env, 0), agents.make(name.replace("crowd", "spacetime"), env, 0)
    assert agent.model.margin == 0.05 > plain.model.margin and agent.model.prediction == plain.model.prediction == "physics"
    assert agent.optimizer == plain.optimizer == name.split("-")[0] and agent.population == plain.population


@pytest.mark.slow  # one maze-crowd episode of ~100 replans: ~30 s on a quiet machine
def test_pso_spacetime_gets_past_the_humans_where_the_rest_past_its_horizon_held_it():
    """maze-crowd validation episode 11 at Δd 0.5: with Eq. 4 charged on the humans the rest's straight
    pieces pass (through walls) the robot stayed behind a human until one walked into it (step 38)."""
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=0.5)
    info = agents.rollout(agents.make("pso-spacetime", env, seed=900000011), env, 900000011)
    assert info["is_success"]


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
                                           ("cone_degrees", {"cone_degrees": 95.0})])  # fmt: skip
@pytest.mark.parametrize("name", PLANNERS)
def test_bad_options_raise_naming_the_field(name, field, kwargs):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    with pytest.raises(ValueError, match=field):
        agents.make(name, env, **kwargs)
