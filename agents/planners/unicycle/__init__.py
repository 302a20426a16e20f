"""Planning over a unicycle's own moves (its speed and turn rate within their limits), flown as the
env flies them (``pathplan_env.robots.arc_contact``).

``astar`` is the space-time A* over the unicycle's moves, ``rollout`` the cost of a control
sequence rolled out along predicted obstacles; the agents are ``astar_agent`` (``astar-unicycle``)
and ``metaheuristic_agent`` (``pso-unicycle``, ``abc-unicycle``). The reactive ``dwa`` and the
``tracked`` pure-pursuit drive are in :mod:`agents.reactive`, the unicycle's clairvoyant limit in
:mod:`agents.oracles.clairvoyant_unicycle`.
"""

from agents.planners.unicycle.astar_agent import UnicycleAStarAgent
from agents.planners.unicycle.metaheuristic_agent import UnicycleMetaheuristicAgent

__all__ = ["UnicycleAStarAgent", "UnicycleMetaheuristicAgent"]
