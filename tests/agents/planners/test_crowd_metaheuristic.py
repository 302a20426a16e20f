"""The paper's space-time optimisers among crowds that steer (maze-crowd): past the horizon a wall scene's
rest of the path may pay nothing on the obstacles its straight pieces pass, and may go round them where the
prediction leaves them (``obstacle_field``); a running cost prefers the plan that closes in first
(``progress_weight``); the crowd variants ``pso-crowd`` / ``abc-crowd`` and the cone prediction act."""

import math

import gymnasium as gym
import numpy as np
import pytest

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.costtogo import STRAIGHT_LINE, around_obstacles, cost_to_go, distance_to_goal
from agents.planners.timed_objective import FIRST_CONTACT, INFEASIBLE, TimedScene, timed_path_cost

PLANNERS = ("pso-spacetime", "abc-spacetime", "pso-crowd", "abc-crowd")


def _scene(field, rest_obstacles: bool, steps: int = 2, disc=(6.0, 1.0), progress_weight: float = 0.0) -> TimedScene:
    """A robot at (1, 1) bound for (9, 1), one disc at rest at ``disc`` (on the straight line past a
    2-step horizon), and ``field`` as the cost-to-go."""
    substeps = 1
    trajectory = np.zeros((steps * substeps + 1, 1, 4))
    trajectory[:, 0, :2] = disc
    return TimedScene(trajectory, substeps, 0.2, np.array([0.3]), np.array([1.0, 1.0]), np.array([9.0, 1.0]), 0.1, 0.25, steps,
                      100.0, np.zeros((steps, 1)), np.zeros((0, 5)), field, FIRST_CONTACT, INFEASIBLE, rest_obstacles,
                      progress_weight)  # fmt: skip


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


def test_the_running_cost_prefers_closing_in_and_waiting_to_wandering_to_the_same_place():
    """Two plans end a 10-step horizon at (2, 1), 1 m on towards the goal: one flies there in 4 steps and
    waits, the other swings out to (1.5, 2.15) and back at top speed. The arrival alone ties them (the
    robot flew the first step of either); ``progress_weight`` > 0 makes the first the cheaper."""
    closing = np.array([2.0, 1.0, 2.0, 1.0, 1.0, 0.0, 0.0])
    wandering = np.array([1.5, 1.0 + math.sqrt(1.25**2 - 0.5**2), 2.0, 1.0, 1.0, 1.0, 0.0])  # 1.25 m out, 1.25 m back
    far = (5.0, 8.0)  # the disc out of the way
    tied = [timed_path_cost(x, _scene(STRAIGHT_LINE, False, 10, far)) for x in (closing, wandering)]
    assert tied[0][1] == tied[1][1] == 0.0 and tied[0][0] == pytest.approx(tied[1][0], abs=1e-9)
    weighted = [timed_path_cost(x, _scene(STRAIGHT_LINE, False, 10, far, 0.1))[0] for x in (closing, wandering)]
    assert weighted[0] < weighted[1] - 0.01
    assert weighted[0] > tied[0][0]  # the running cost adds to the arrival


def _corridor_field(radius: float):
    """A corridor 2 m wide (walls at y = 0 and 2 in the maze's box), the goal at its right end, and the
    static field with and without a disc of ``radius`` at (5, 1) standing in it."""
    env = gym.make("DynamicObstacle-v0", scenario="maze")
    box = agents.make("pso-spacetime", env, 0).facts.arena.box
    walls = np.array([[0.0, 0.0, 9.8, 0.0, 0.05], [0.0, 2.0, 9.8, 2.0, 0.05]])
    goal = np.array([9.0, 1.0])
    static = cost_to_go(goal, 0.1, box, walls, 0.2)
    return static, around_obstacles(static, goal, 0.1, box, walls, 0.2, np.array([[5.0, 1.0]]), np.array([radius]))


def test_the_field_goes_round_an_obstacle_standing_where_the_prediction_leaves_it():
    """Behind a disc in the corridor the way to the goal is longer round it than the static field says; past
    it nothing changes, and nowhere is it shorter; a disc that closes the corridor leaves the cells behind it
    dearer than any the goal can be reached from, and finite (it will move on)."""
    def d(f, x, y):
        return distance_to_goal(f, x, y, 9.0, 1.0, 0.1)

    static, around = _corridor_field(0.4)  # a way past it on either side
    assert d(around, 4.5, 1.0) > d(static, 4.5, 1.0) + 0.15 and d(around, 4.0, 1.0) > d(static, 4.0, 1.0) + 0.08
    assert d(around, 6.5, 1.0) == d(static, 6.5, 1.0)  # past it
    finite = np.isfinite(static.field)
    assert (np.isfinite(around.field) == finite).all() and (around.field[finite] >= static.field[finite]).all()
    assert around.field.shape == static.field.shape and around.cell == static.cell
    static, closed = _corridor_field(0.8)  # the disc (with the robot's radius) spans the corridor
    past = finite & (static.x0 + (np.arange(static.field.shape[0])[:, None] + 0.5) * static.cell > 6.0)
    assert np.isfinite(d(closed, 3.0, 1.0)) and d(closed, 3.0, 1.0) > closed.field[past].max() + d(static, 3.0, 1.0) - 0.1
    no_walls = around_obstacles(STRAIGHT_LINE, np.array([9.0, 1.0]), 0.1, None, np.zeros((0, 5)), 0.2, np.array([[5.0, 1.0]]), np.array([0.3]))
    assert no_walls is STRAIGHT_LINE


@pytest.mark.parametrize("name", ["pso-crowd", "abc-crowd"])
def test_registry_makes_the_crowd_variants_with_a_wider_margin(name):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    agent, plain = agents.make(name, env, 0), agents.make(name.replace("crowd", "spacetime"), env, 0)
    assert agent.model.margin == 0.05 > plain.model.margin and agent.model.prediction == plain.model.prediction == "physics"
    assert agent.timed_problem(env.reset(seed=0)[0]).rest_obstacles is False and plain.rest_obstacles is True
    assert agent.obstacle_field is True and plain.obstacle_field is False and agent.progress_weight == plain.progress_weight == 0.0
    assert agent.optimizer == plain.optimizer == name.split("-")[0] and agent.population == plain.population


@pytest.mark.slow  # one maze-crowd episode of ~100 replans and one of 38: ~40 s on a quiet machine
def test_pso_spacetime_gets_past_the_humans_where_the_rest_past_its_horizon_held_it():
    """maze-crowd validation episode 11 at Δd 0.5: with Eq. 4 charged on the humans the rest's straight
    pieces pass (through walls) the robot stays behind a human until one walks into it (step 38); with
    ``rest_obstacles=False`` it reaches the goal."""
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=0.5)
    charged = agents.rollout(agents.make("pso-spacetime", env, seed=900000011, steering="ignore"), env, 900000011)
    assert charged["collision"]
    unpaid = agents.rollout(agents.make("pso-spacetime", env, seed=900000011, rest_obstacles=False, steering="ignore"), env, 900000011)
    assert unpaid["is_success"]


@pytest.mark.slow  # two maze-crowd episodes, one of 200 replans: ~15 s on a quiet machine
def test_pso_crowd_walks_round_the_humans_where_the_static_field_held_it_behind_them():
    """maze-crowd validation episode 8 at Δd 1: humans walk up into the doorway the robot must pass; with the
    static field past the horizon the swarm waits (and wanders) behind them until the time limit; with the
    field round them where the prediction leaves them (``obstacle_field``, pso-crowd's) it reaches the goal."""
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd", delta_d=1.0)
    static = agents.rollout(agents.make("pso-crowd", env, seed=900000008, obstacle_field=False, steering="ignore"), env, 900000008)
    assert not static["is_success"] and not static["collision"]
    around = agents.rollout(agents.make("pso-crowd", env, seed=900000008), env, 900000008)
    assert around["is_success"]


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
                                           ("cone_degrees", {"cone_degrees": 95.0}), ("rest_obstacles", {"rest_obstacles": "no"}),
                                           ("progress_weight", {"progress_weight": -0.1}), ("progress_weight", {"progress_weight": "x"}),
                                           ("obstacle_field", {"obstacle_field": "yes"})])  # fmt: skip
@pytest.mark.parametrize("name", PLANNERS)
def test_bad_options_raise_naming_the_field(name, field, kwargs):
    env = gym.make("DynamicObstacle-v0", scenario="maze-crowd")
    with pytest.raises(ValueError, match=field):
        agents.make(name, env, **kwargs)
