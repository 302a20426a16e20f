"""The project's agent families: one per method, the axes it varies along as its parameters.

Each family's factory turns its axes into the constructor's settings; what ``tuning="crowd"``
sets is each family's own constant (``CROWD_SETTINGS`` beside the planner that reads it), named
in the preset table (``docs/agents.md``, written by ``scripts/agent_tables.py``).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from agents.oracles import ClairvoyantOracle, StaticOracleAgent
from agents.planners import MetaheuristicAgent, SpacetimeAStarAgent, SpacetimeMetaheuristicAgent
from agents.planners.spacetime import astar_agent as spacetime_astar
from agents.planners.spacetime import metaheuristic_agent as spacetime_metaheuristic
from agents.planners.unicycle import astar_agent as unicycle_astar
from agents.planners.unicycle import metaheuristic_agent as unicycle_metaheuristic
from agents.planners.unicycle.astar_agent import UnicycleAStarAgent
from agents.planners.unicycle.metaheuristic_agent import UnicycleMetaheuristicAgent
from agents.reactive import ORCAAgent, StraightAgent, VelocityObstacleAgent
from agents.reactive.dwa import DWAAgent
from agents.reactive.dwa_lidar import LidarDWAAgent
from agents.reactive.tracker import TrackedAgent
from agents.registry import factory, register
from agents.requirements import GOAL_KEYS, LIDAR_KEYS, STATE_KEYS
from agents.rl.lidar.policy import LidarRLAgent
from agents.rl.obstacle_set.policy import SetRLAgent
from agents.rl.policy import MODELS_DIR
from agents.rl.sarl.policy import SARLAgent
from agents.rl.sb3_model import SB3Agent, trained_agent

#: What a planner plans: one intermediate waypoint a step (the paper), a timed path in space-time
#: over a horizon, or the unicycle's own (v, ω) controls.
PLANS = ("waypoint", "spacetime", "controls")
#: ``"default"``: as validated among bouncing discs; ``"crowd"``: for crowds that steer (the family's CROWD_SETTINGS).
TUNINGS = ("default", "crowd")
#: The waypoint planners' prediction: none (the paper: obstacles where they are) or along their velocities.
WAYPOINT_PREDICTIONS = ("none", "constant-velocity")
#: The learned PPO agents by the observation they read.
PPO_OBSERVATIONS = ("state", "lidar", "set")
#: The shipped PPO models that read the single env's "state" features: one robot among obstacles
#: (``ppo``), and one policy for every robot of the multi-robot circle (``ppo_multi``, agents.rl.multi_robot).
PPO_STATE_MODELS = ("ppo", "ppo_multi")
#: What DWA reads of the obstacles: the state's list (positions and velocities) or the lidar's scan.
DWA_SENSORS = ("state", "lidar")

UNICYCLE = ("unicycle",)
HOLONOMIC = ("holonomic",)
BOTH = ("holonomic", "unicycle")

PLANNER_AXES = MappingProxyType({
    "plan": f"what is optimised: {', '.join(PLANS)}",
    "variant": "with plan='waypoint': the paper's optimiser or the textbook one (paper, vanilla)",
    "prediction": "how obstacles are predicted: none, constant-velocity (waypoint plans); physics, cone (the others)",
    "tuning": f"{', '.join(TUNINGS)} (crowd: for crowds that steer)",
})  # fmt: skip


def _choice(argument: str, value, choices) -> str:
    if value not in choices:
        raise ValueError(f"{argument} must be one of {choices}, got {value!r}")
    return value


def _crowd(tuning: str, settings: Mapping[str, Any], crowd: Mapping[str, Any]) -> dict[str, Any]:
    """The settings with a tuning's constants under the caller's own (an explicit setting wins)."""
    return {**(crowd if _choice("tuning", tuning, TUNINGS) == "crowd" else {}), **settings}


def _plans_controls(parameters: Mapping[str, Any]) -> tuple[str, ...]:
    return UNICYCLE if parameters.get("plan") == "controls" else HOLONOMIC


def metaheuristic(env, seed: int | None = None, *, optimizer: str = "pso", plan: str = "waypoint", variant: str = "paper",
                  prediction: str | None = None, tuning: str = "default", **settings):  # fmt: skip
    """The paper's optimisers (``optimizer``: ``pso``, ``abc``) on what ``plan`` names."""
    _choice("plan", plan, PLANS)
    if plan == "waypoint":
        if tuning != "default":
            raise ValueError(f"tuning={tuning!r}: the waypoint planners have one tuning (the paper's); plan='spacetime' has 'crowd'")
        predictive = _choice("prediction", "none" if prediction is None else prediction, WAYPOINT_PREDICTIONS) != "none"
        return MetaheuristicAgent(env, seed, optimizer=optimizer, variant=variant, predictive=predictive, **settings)
    if variant != "paper":
        raise ValueError(f"variant={variant!r}: plan={plan!r} runs the paper's optimisers only; variant applies to plan='waypoint'")
    if optimizer == "abc":
        settings.setdefault("population", 40)  # 20 food sources
    if prediction is not None:
        settings["prediction"] = prediction
    if plan == "spacetime":
        return SpacetimeMetaheuristicAgent(env, seed, optimizer=optimizer, **_crowd(tuning, settings, spacetime_metaheuristic.CROWD_SETTINGS))
    return UnicycleMetaheuristicAgent(env, seed, optimizer=optimizer, **_crowd(tuning, settings, unicycle_metaheuristic.CROWD_SETTINGS))


def pso(env, seed: int | None = None, **parameters):
    """The paper's adaptive constraint PSO (:func:`metaheuristic` with ``optimizer="pso"``)."""
    return metaheuristic(env, seed, **{"optimizer": "pso", **parameters})  # optimizer= still overrides, as in 0.1.0


def abc(env, seed: int | None = None, **parameters):
    """The paper's modified ABC (:func:`metaheuristic` with ``optimizer="abc"``)."""
    return metaheuristic(env, seed, **{"optimizer": "abc", **parameters})


def astar(env, seed: int | None = None, *, plan: str = "spacetime", tuning: str = "default", **settings):
    """Space-time A* over the holonomic robot's moves (``plan="spacetime"``) or the unicycle's (``"controls"``)."""
    if _choice("plan", plan, PLANS) == "waypoint":
        raise ValueError("plan='waypoint': A* plans a path (plan='spacetime') or the unicycle's controls (plan='controls')")
    if plan == "spacetime":
        return SpacetimeAStarAgent(env, seed, **_crowd(tuning, settings, spacetime_astar.CROWD_SETTINGS))
    return UnicycleAStarAgent(env, seed, **_crowd(tuning, settings, unicycle_astar.CROWD_SETTINGS))


def ppo(env, seed: int | None = None, *, observation: str = "state", model: str | None = None, **settings):
    """The learned PPO agents by the observation they read: the shipped model of each (``model``: which
    shipped "state" model, :data:`PPO_STATE_MODELS`), or ``path=``."""
    if model is not None:
        if _choice("observation", observation, PPO_OBSERVATIONS) != "state" or "path" in settings:
            raise ValueError(f"model={model!r} names a shipped 'state' model: give it without observation={observation!r} or path=")
        settings["path"] = MODELS_DIR / f"{_choice('model', model, PPO_STATE_MODELS)}.zip"
    build = {"state": trained_agent, "lidar": LidarRLAgent, "set": SetRLAgent}[_choice("observation", observation, PPO_OBSERVATIONS)]
    return build(env, seed, **settings)


def dwa(env, seed: int | None = None, *, sensor: str = "state", **settings):
    """The dynamic window approach on the obstacle list (``sensor="state"``) or the range scan (``"lidar"``)."""
    build = {"state": DWAAgent, "lidar": LidarDWAAgent}[_choice("sensor", sensor, DWA_SENSORS)]
    return build(env, seed, **settings)


def _ppo_reads(parameters: Mapping[str, Any]) -> tuple[str, ...]:
    return LIDAR_KEYS if parameters.get("observation") == "lidar" else STATE_KEYS


def _dwa_reads(parameters: Mapping[str, Any]) -> tuple[str, ...]:
    return LIDAR_KEYS if parameters.get("sensor") == "lidar" else STATE_KEYS


def _tracked_reads(parameters: Mapping[str, Any]) -> tuple[str, ...] | None:
    """What the followed planner reads (a factory of one's own: not stated)."""
    planner = parameters.get("planner", "astar-spacetime")
    if not isinstance(planner, str):
        return None
    recipe = factory(planner)
    return recipe.family.observations_with(recipe.parameters)


def register_families() -> None:
    """Register the project's families (``import agents`` does)."""
    register("straight", StraightAgent, summary="always aims at the goal", waypoints=True, observations=GOAL_KEYS)
    register("velocity-obstacle", VelocityObstacleAgent, waypoints=True, observations=STATE_KEYS,
             summary="classical reactive velocity obstacles: the admissible velocity closest to the preferred one")  # fmt: skip
    register("orca", ORCAAgent, waypoints=True, observations=STATE_KEYS,
             summary="ORCA (van den Berg et al. 2011) as the robot's policy, CrowdNav's baseline: it assumes every obstacle reciprocates")  # fmt: skip
    register("dwa", dwa, robots=UNICYCLE, observations_for=_dwa_reads,
             axes={"sensor": f"what it reads of the obstacles: {', '.join(DWA_SENSORS)} (the scan's returns as still points)"},
             summary="the dynamic window approach (Fox et al. 1997) on the unicycle's velocities, from the obstacle list or the lidar")  # fmt: skip
    for name, build, what in (("pso", pso, "the paper's adaptive constraint PSO"), ("abc", abc, "the paper's modified ABC")):
        register(name, build, waypoints=True, robots_for=_plans_controls, axes=PLANNER_AXES, observations=STATE_KEYS,
                 summary=f"{what}: one waypoint a step (the paper), a timed space-time path, or the unicycle's controls")  # fmt: skip
    register("astar", astar, waypoints=True, robots_for=_plans_controls, observations=STATE_KEYS,
             axes={"plan": "spacetime, controls (the unicycle's own moves)", "prediction": "physics, cone", "tuning": PLANNER_AXES["tuning"]},
             summary="A* over (step, position) on the predicted obstacles: model-based planning without a metaheuristic")  # fmt: skip
    register("oracle-static", StaticOracleAgent, waypoints=True, observations=STATE_KEYS,
             summary="the exact shortest path among the current obstacles and walls, replanned every step; blind to motion")  # fmt: skip
    register("oracle-clairvoyant", ClairvoyantOracle, robots=BOTH, observations=GOAL_KEYS,
             summary="privileged: reads the simulator; the earliest collision-free arrival, the harness's limit")  # fmt: skip
    register("ppo", ppo, observations_for=_ppo_reads,
             axes={"observation": f"the input the network reads: {', '.join(PPO_OBSERVATIONS)}", "path": "a model file (default: shipped)",
                   "model": f"a shipped 'state' model: {', '.join(PPO_STATE_MODELS)} (ppo_multi: one policy for every robot of the multi-robot circle)"},
             summary="stable-baselines3 PPO policies, shipped with a numpy forward (no torch)")  # fmt: skip
    register("sarl", SARLAgent, observations=STATE_KEYS,
             axes={"model": "the shipped network: sarl_crowdnav, sarl_random, sarl_crowdnav_crossings", "path": "a model file"},
             summary="a SARL value network (Chen et al. 2019) with attention over the humans and a two-step lookahead")  # fmt: skip
    register("sb3", SB3Agent, robots=BOTH, axes={"path": "the model file (required)"},
             summary="any stable-baselines3 model file as it comes, its VecNormalize statistics applied")  # fmt: skip
    register("tracked", TrackedAgent, robots=UNICYCLE, observations_for=_tracked_reads, axes={"planner": "the waypoint planner followed (a name or a factory)"},
             summary="pure pursuit of any waypoint planner's plan on the unicycle (drive='pure-pursuit')")  # fmt: skip
