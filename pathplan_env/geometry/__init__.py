"""Geometry: the discs' continuous contact test (``contacts``), walls as capsules (``walls``), exact ray casting
(``rays``) and the shortest path among circles (``shortest_paths``)."""

# the names of pathplan_env.geometry in 0.1.0, when it was one module, from their homes

from pathplan_env.arena import Arena
from pathplan_env.geometry.contacts import NO_CONTACT, point_segment_distance, segment_segment_distance, swept_contact, swept_pair
from pathplan_env.geometry.reference_path import shortest_path_to_goal
from pathplan_env.geometry.shortest_paths import shortest_path

__all__ = [
    "Arena", "NO_CONTACT", "point_segment_distance", "segment_segment_distance", "shortest_path", "shortest_path_to_goal", "swept_contact",
    "swept_pair",
]  # fmt: skip
