"""Policies for DynamicObstacle-v0 with SB3's ``predict`` contract, as families with parameters.

``agents.make(name, env, seed=None, **parameters)`` builds one: ``name`` is a family (``pso``,
``astar``, ``orca``, ...; ``agents.families()``) or a preset, a family with some parameters set
(``pso-spacetime`` is ``pso`` with ``plan="spacetime"``; ``agents.presets()``). ``agents.available()``
lists both.

``import agents`` first checks that this folder holds our files only (:mod:`agents._ownership`: pip
merges ``openai-agents``' own top-level ``agents`` into it without a word); ``import pathplan_agents``
is the import path that always reaches this package.
"""

from agents import _ownership  # noqa: F401, I001  (first: it checks the folder holds our files only, before anything else is read from it)

from agents.base import Agent, rollout
from agents.families import register_families
from agents.oracles import ClairvoyantOracle, StaticOracleAgent
from agents.planners import MetaheuristicAgent, SpacetimeAStarAgent, SpacetimeMetaheuristicAgent
from agents.planners.unicycle.astar_agent import UnicycleAStarAgent
from agents.planners.unicycle.metaheuristic_agent import UnicycleMetaheuristicAgent
from agents.presets import register_presets
from agents.reactive import ORCAAgent, StraightAgent, VelocityObstacleAgent
from agents.reactive.dwa import DWAAgent
from agents.reactive.tracker import TrackedAgent
from agents.registry import (
    available,
    check,
    families,
    family_of,
    make,
    observation_of,
    observations_of,
    presets,
    register,
    register_preset,
    robots_of,
)
from agents.rl import RLAgent

register_families()
register_presets()

#: Marks this ``agents`` as pathplan-env's (``pathplan_agents`` checks it).
PATHPLAN_ENV = True

#: The registered agents that drive only a unicycle (``gym.make(..., robot="unicycle")``): read from the registry.
UNICYCLE_AGENTS = frozenset(name for name in available() if robots_of(name) == ("unicycle",))

__all__ = [
    "Agent", "ClairvoyantOracle", "DWAAgent", "TrackedAgent", "UnicycleAStarAgent", "MetaheuristicAgent", "ORCAAgent", "RLAgent",
    "SpacetimeAStarAgent", "SpacetimeMetaheuristicAgent", "StaticOracleAgent", "StraightAgent", "UNICYCLE_AGENTS",
    "UnicycleMetaheuristicAgent", "VelocityObstacleAgent",
    "available", "check", "families", "family_of", "make", "observation_of", "observations_of", "presets", "register", "register_preset",
    "robots_of", "rollout",
]  # fmt: skip
