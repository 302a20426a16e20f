"""The multi-robot env beside navground-learning's PettingZoo env (PyPI ``navground-learning``, on
navground's C++ core), on one scene built in both from the same lists: ``n`` robots on a 3 m circle
among CrowdNav's circle-crossing ORCA humans (``multi-crowd``'s scene with ``humans`` humans), for
``scripts/bench_multi_robot.py --navground``.

Both sides step every robot's observation of every other body: ours the default Dict observation
(every other robot and human a row), navground's a ``Discs`` sensor of as many discs within 10 m with
the target's direction and distance and the robot's velocity. The robots hold still (ours: the waypoint
at the robot; navground's: a zero velocity command), so no robot leaves either world and both step the
same bodies; the humans walk with ORCA, seeing the robots, in both (the ORCA parameters of
``pathplan_env.world.navground_peer``). navground is imported only when its env is built.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from pathplan_env.multi_robot.presets import multi_crowd
from pathplan_env.multi_robot.scene import MultiScenario
from pathplan_env.world.navground_peer import DT, MAX_NEIGHBORS, NEIGHBOR_DIST, RADIUS_PADDING, TIME_HORIZON


def crowd_scene(robots: int, humans: int, seed: int = 0) -> MultiScenario:
    """``robots`` robots on a 3 m circle among ``humans`` CrowdNav circle-crossing humans, drawn from
    ``seed``, at the control period of ``pathplan_env.world.navground_peer`` (0.1 s)."""
    scene = multi_crowd(np.random.default_rng(seed), robots, humans)
    return scene.with_world(dataclasses.replace(scene.world, dt=DT))


def ours_stepper(scene: MultiScenario) -> Callable:
    """A fresh multi-robot env of ``scene`` (reset) and its step, every robot holding still."""
    from pathplan_env.multi_robot.env import MultiRobotEnv

    env = MultiRobotEnv(scenario=scene, max_steps=10_000)
    env.reset(seed=0)
    hold = {agent: env.robot_env(agent).waypoint_to_action(np.array(env.robot_scenario(agent).start)) for agent in env.agents}

    def step():
        # (a human that grazes a robot takes it out of the episode: the others go on)
        return env.step({agent: hold[agent] for agent in env.agents})

    step.env = env
    return step


def _orca(speed: float):
    import navground.core as core

    behavior = core.behaviors.ORCABehavior()
    behavior.time_horizon = behavior.static_time_horizon = TIME_HORIZON
    behavior.max_number_of_neighbors = MAX_NEIGHBORS
    behavior.safety_margin = RADIUS_PADDING
    behavior.optimal_speed = speed
    return behavior


def navground_env(scene: MultiScenario):
    """``scene`` as navground-learning's PettingZoo env (``shared_parallel_env``): its robots the
    controlled agents (indices ``0..n-1``), its humans navground's own ORCA agents."""
    import navground.core as core
    import navground.sim as sim
    from navground.learning import indices
    from navground.learning.config import ControlActionConfig, DefaultObservationConfig
    from navground.learning.parallel_env import shared_parallel_env

    world_spec = scene.world
    bodies = [(r.start, r.goal, world_spec.robot_radius, world_spec.robot_speed) for r in scene.robots]
    bodies += [(ob.center, ob.goal, ob.radius, ob.preferred_speed) for ob in world_spec.obstacles]

    class Scene(sim.Scenario):
        def init_world(self, world, seed=None):
            super().init_world(world, seed)
            for start, goal, radius, speed in bodies:
                agent = sim.Agent(
                    radius=radius, behavior=_orca(speed), kinematics=core.kinematics.OmnidirectionalKinematics(speed, 1.0),
                    task=sim.tasks.WaypointsTask([goal], False, 0.01),
                    state_estimations=[sim.state_estimations.BoundedStateEstimation(range=NEIGHBOR_DIST)], control_period=world_spec.dt,
                )  # fmt: skip
                agent.position = start
                world.add_agent(agent)

    others = len(bodies) - 1
    sensor = sim.load_state_estimation(
        f"{{type: Discs, number: {others}, range: {NEIGHBOR_DIST}, max_speed: {max(b[3] for b in bodies)}, max_radius: {max(b[2] for b in bodies)}}}"
    )
    observation = DefaultObservationConfig(include_target_direction=True, include_target_distance=True, include_velocity=True)
    return shared_parallel_env(scenario=Scene(), indices=indices.Indices(set(range(scene.n_robots))), sensor=sensor,
                               action=ControlActionConfig(fix_orientation=True), observation=observation, time_step=world_spec.dt)  # fmt: skip


def navground_stepper(scene: MultiScenario) -> Callable:
    """A fresh navground-learning env of ``scene`` (reset) and its step, every robot holding still."""
    env = navground_env(scene)
    env.reset(seed=0)
    hold = {agent: np.zeros(env.action_space(agent).shape, np.float32) for agent in env.agents}
    return lambda: env.step(hold)


__all__ = ["crowd_scene", "navground_env", "navground_stepper", "ours_stepper"]
