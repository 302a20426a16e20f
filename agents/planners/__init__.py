"""Planners that optimise or search a path every step: the paper's metaheuristics (``metaheuristic``,
``pso``, ``bee_colony``, ``objective``) and their space-time versions (``spacetime``,
``spacetime_search``), which predict the obstacles from the observation (``prediction``)."""

from agents.planners.metaheuristic import MetaheuristicAgent
from agents.planners.spacetime import SpacetimeAStarAgent
from agents.planners.spacetime_metaheuristic import SpacetimeMetaheuristicAgent

__all__ = ["MetaheuristicAgent", "SpacetimeAStarAgent", "SpacetimeMetaheuristicAgent"]
