"""Scenarios: the record (``scenario``), the presets (``presets``) with their families (``wall_families``,
``crowd_families``, ``crowdnav``), scenes on maps (``on_maps``), files (``files``) and seed splits (``splits``)."""

# the names of pathplan_env.scenarios in 0.1.0, when it was one module, from their homes

from pathplan_env.arena import Arena
from pathplan_env.arguments import check_count, check_delta_d, check_n_obstacles
from pathplan_env.crowds.behaviours import BOUNCE, make_behaviour
from pathplan_env.geometry.walls import DEFAULT_WALL_THICKNESS, as_point, check_static_geometry, normalise_polygons, normalise_walls, segments_of
from pathplan_env.scenarios.scenario import MAX_COORDINATE, MIN_LENGTH, Obstacle, Scenario

__all__ = [
    "Arena", "BOUNCE", "DEFAULT_WALL_THICKNESS", "MAX_COORDINATE", "MIN_LENGTH", "Obstacle", "Scenario", "as_point", "check_count",
    "check_delta_d", "check_n_obstacles", "check_static_geometry", "make_behaviour", "normalise_polygons", "normalise_walls", "segments_of",
]  # fmt: skip
