"""Policies for DynamicObstacle-v0 with SB3's ``predict`` contract.

``agents.make(name, env, seed=None, **overrides)`` builds one; ``agents.available()`` lists them.
"""

from functools import partial

from agents.base import Agent, available, make, register, robots_of, rollout
from agents.oracles import ClairvoyantOracle, StaticOracleAgent
from agents.planners import MetaheuristicAgent, SpacetimeAStarAgent, SpacetimeMetaheuristicAgent
from agents.planners.spacetime import CROWD_SETTINGS as ASTAR_CROWD_SETTINGS
from agents.planners.spacetime_metaheuristic import CROWD_SETTINGS
from agents.planners.unicycle_astar import UnicycleAStarAgent
from agents.planners.unicycle_metaheuristic import UnicycleMetaheuristicAgent
from agents.reactive import ORCAAgent, StraightAgent, VelocityObstacleAgent
from agents.reactive.dwa import DWAAgent
from agents.reactive.tracker import TrackedAgent
from agents.rl import RLAgent
from agents.rl.lidar.policy import LidarRLAgent
from agents.rl.obstacle_set.policy import SetRLAgent
from agents.rl.sarl.policy import SARLAgent
from agents.rl.sb3_model import SB3Agent, trained_agent

register("straight", StraightAgent)
register("velocity-obstacle", VelocityObstacleAgent)
register("orca", ORCAAgent)
register("oracle-static", StaticOracleAgent)
register("oracle-clairvoyant", ClairvoyantOracle, robots=("holonomic", "unicycle"))  # privileged: reads the simulator (the unicycle's own search on a unicycle)
register("ppo", partial(trained_agent, algo="ppo"))  # the shipped PPO; with path=: a train_rl.py model, or any PPO .zip
register("ppo-lidar", LidarRLAgent)  # the shipped lidar PPO (1-D conv encoder): observation="lidar"; with path=: a train_rl.py --observation lidar model
register("ppo-set", SetRLAgent)  # the set-encoder PPO (attention over every obstacle); with path=: a train_rl.py --observation set model
register("sarl", SARLAgent)  # value network with attention + lookahead on predicted humans (two steps, RGL), a grid search when all stand (sarl_crowdnav.npz)
register("sarl-random", partial(SARLAgent, model="sarl_random"))  # the same trained on random scenes, bouncing obstacles (sarl_random.npz, setting per sidecar)
register("sarl-crossings", partial(SARLAgent, model="sarl_crowdnav_crossings"))  # the same trained on CrowdNav's circle and square crossings by turns
register("sb3", SB3Agent, robots=("holonomic", "unicycle"))  # any SB3 model file as it comes, path= required (agents.rl.sb3_model)
register("astar-spacetime", SpacetimeAStarAgent)
# for crowds that steer: a cone of predicted futures, a wider margin, and an escape when every plan ends in contact
register("astar-crowd", partial(SpacetimeAStarAgent, **ASTAR_CROWD_SETTINGS))
for _optimizer in ("pso", "abc"):
    register(_optimizer, partial(MetaheuristicAgent, optimizer=_optimizer, variant="paper"))
    register(f"{_optimizer}-vanilla", partial(MetaheuristicAgent, optimizer=_optimizer, variant="vanilla"))
    register(f"{_optimizer}-predictive", partial(MetaheuristicAgent, optimizer=_optimizer, variant="paper", predictive=True))
register("pso-spacetime", partial(SpacetimeMetaheuristicAgent, optimizer="pso"))
register("abc-spacetime", partial(SpacetimeMetaheuristicAgent, optimizer="abc", population=40))  # 20 food sources
# pso-/abc-spacetime's crowd settings from the first step on (those two take them once they see the obstacles
# steer, agents.planners.steering): a 5 % margin (a human who swerves walks into a plan that grazes it) and, with walls,
# no Eq. 4 on the humans the rest of the path past the horizon passes (its pieces may cut walls: the charge
# held the robot behind slow humans in the maze), but the cost-to-go from where the horizon leaves the robot
# goes round the humans where the prediction leaves them (without it the swarm waited behind a human in a
# maze doorway that astar-spacetime walked round); astar-crowd's cone of futures did no better on validation
# and held the robot back in the maze's corridors (docs/results/maps_first_look/README.md)
register("pso-crowd", partial(SpacetimeMetaheuristicAgent, optimizer="pso", **CROWD_SETTINGS))
register("abc-crowd", partial(SpacetimeMetaheuristicAgent, optimizer="abc", population=40, **CROWD_SETTINGS))
UNICYCLE = ("unicycle",)
# the unicycle (robot="unicycle"): the dynamic window approach, and any waypoint planner driven by pure pursuit
register("dwa", DWAAgent, robots=UNICYCLE)
register("astar-unicycle", UnicycleAStarAgent, robots=UNICYCLE)  # space-time A* over the unicycle's own moves (agents.planners.unicycle_search)
# for crowds that steer, as astar-crowd: a cone of three predicted futures per obstacle and a 15 % margin
register("astar-unicycle-crowd", partial(UnicycleAStarAgent, prediction="cone", margin=0.15, retry_factor=5), robots=UNICYCLE)
register("tracked", TrackedAgent, robots=UNICYCLE)  # agents.make("tracked", env, planner="pso-spacetime")
for _planner in ("astar-spacetime", "astar-crowd", "pso-spacetime", "abc-spacetime", "pso", "abc", "velocity-obstacle", "orca",
                 "oracle-static", "straight"):  # fmt: skip
    register(f"tracked-{_planner}", partial(TrackedAgent, planner=_planner), robots=UNICYCLE)
# the paper's optimisers on the unicycle's own control sequence
register("pso-unicycle", partial(UnicycleMetaheuristicAgent, optimizer="pso"), robots=UNICYCLE)
register("abc-unicycle", partial(UnicycleMetaheuristicAgent, optimizer="abc", population=40), robots=UNICYCLE)  # 20 food sources
# for crowds that steer (CrowdNav's circle crossing): the cone of predicted futures and a 10 % margin
register("pso-unicycle-crowd", partial(UnicycleMetaheuristicAgent, optimizer="pso", prediction="cone", margin=0.1), robots=UNICYCLE)
register("abc-unicycle-crowd", partial(UnicycleMetaheuristicAgent, optimizer="abc", population=40, prediction="cone", margin=0.1), robots=UNICYCLE)
#: The registered agents that drive only a unicycle (``gym.make(..., robot="unicycle")``): read from the registry.
UNICYCLE_AGENTS = frozenset(name for name in available() if robots_of(name) == UNICYCLE)

__all__ = [
    "Agent", "ClairvoyantOracle", "DWAAgent", "TrackedAgent", "UnicycleAStarAgent", "MetaheuristicAgent", "ORCAAgent", "RLAgent",
    "SpacetimeAStarAgent", "SpacetimeMetaheuristicAgent", "StaticOracleAgent", "StraightAgent", "UNICYCLE_AGENTS",
    "UnicycleMetaheuristicAgent", "VelocityObstacleAgent",
    "available", "make", "register", "robots_of", "rollout",
]  # fmt: skip
