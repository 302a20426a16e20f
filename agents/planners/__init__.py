"""Planners that optimise or search a path every step: the paper's metaheuristics (``metaheuristic``,
``pso``, ``bee_colony``, ``objective``) and their space-time versions (``spacetime``,
``spacetime_search``), which predict the obstacles from the observation (``prediction``)."""

from .metaheuristic import MetaheuristicAgent
from .spacetime import SpacetimeAStarAgent
from .spacetime_metaheuristic import SpacetimeMetaheuristicAgent

__all__ = ["MetaheuristicAgent", "SpacetimeAStarAgent", "SpacetimeMetaheuristicAgent"]
