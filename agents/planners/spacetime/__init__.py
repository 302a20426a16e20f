"""Planning in space-time: where the robot is *when*, against predicted obstacles.

``astar`` is the earliest-arrival A* (the same search the clairvoyant oracle runs on the true
trajectories), ``anytime`` the partial plans it returns when its budget runs out, ``seeds`` the
search seeds of the metaheuristics; the agents are ``astar_agent`` (``astar-spacetime``,
``astar-crowd``: :class:`SpacetimeModel` and :class:`SpacetimeAStarAgent`) and
``metaheuristic_agent`` (``pso-spacetime``, ``abc-spacetime``).

This package was the module ``agents.planners.spacetime`` in 0.1.0: its names still read from here
(the module's content is ``astar_agent``).
"""

import importlib

from agents.planners.spacetime.astar_agent import CROWD_SETTINGS, SpacetimeAStarAgent, SpacetimeModel

__all__ = ["CROWD_SETTINGS", "SpacetimeAStarAgent", "SpacetimeModel"]


def __getattr__(name: str):
    """0.1.0's other names of the module ``agents.planners.spacetime`` (read from ``astar_agent``)."""
    if name.startswith("__"):
        raise AttributeError(name)
    module = importlib.import_module("agents.planners.spacetime.astar_agent")
    try:
        return getattr(module, name)
    except AttributeError:
        raise AttributeError(f"module 'agents.planners.spacetime' has no attribute {name!r}") from None
