"""Planners that optimise or search a path every step: the paper's metaheuristics (``metaheuristic``,
``pso``, ``bee_colony``, ``objective``), which predict the obstacles from the observation
(``prediction``), planning in space-time (the ``spacetime`` package: A* and PSO/ABC over where the
robot is *when*) and over a unicycle's own moves (the ``unicycle`` package)."""

from agents.planners.metaheuristic import MetaheuristicAgent
from agents.planners.spacetime.astar_agent import SpacetimeAStarAgent
from agents.planners.spacetime.metaheuristic_agent import SpacetimeMetaheuristicAgent

__all__ = ["MetaheuristicAgent", "SpacetimeAStarAgent", "SpacetimeMetaheuristicAgent"]
