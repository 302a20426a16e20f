"""A recorded episode drawn frame by frame with the env's own renderer (:class:`~pathplan_env.rendering.Renderer`),
from the record alone: the same calls with the same numbers as ``env.render()`` makes during a live
run, so the frames are the same pixels (tested)."""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from pathplan_env.records.trajectory import Episode


def outcome_mark(success: bool, collision: bool) -> str:
    """What a caption adds on the step that ended an episode."""
    return " (goal)" if success else " (collision)" if collision else ""


def frames(episode: Episode, caption: Callable[[int, str], str] | None = None, size: int = 600) -> Iterator[np.ndarray]:
    """Row 0 (after the reset) to the last step as RGB arrays (H, W, 3). ``caption(step, mark)``,
    if given, writes the text at the top left (``mark``: :func:`outcome_mark` of that step)."""
    from pathplan_env.rendering import Renderer  # pygame is imported lazily, only when rendering

    scenario = episode.scenario
    renderer = Renderer(scenario.bounds, "rgb_array", fps=10, size=size)
    trail = [scenario.start]
    try:
        for k in range(episode.steps + 1):
            x, y, heading = episode.robot[k]
            if k:
                trail.append((float(x), float(y)))
            waypoint = episode.waypoint[k]
            overlay = {}
            if episode.beams is not None:
                overlay["beams"] = episode.beams[k]
            if episode.hidden is not None:
                overlay["hidden"] = episode.hidden[k]
            text = caption(k, outcome_mark(bool(episode.success[k]), bool(episode.collision[k]))) if caption else None
            yield renderer.draw(scenario=scenario, obstacle_state=episode.obstacles[k], radii=episode.radii, robot_position=np.array((x, y)),
                                trail=trail, waypoint=None if np.isnan(waypoint[0]) else (float(waypoint[0]), float(waypoint[1])),
                                plan=episode.plan(k), caption=text, heading=float(heading) if episode.turns else None, **overlay)  # fmt: skip
    finally:
        renderer.close()
