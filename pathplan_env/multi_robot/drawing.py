"""A frame of the multi-robot env (``render_mode="rgb_array"``): matplotlib off-screen (Agg), no display.

Robots in colour with their trails, goals (crosses) and plans (``env.planned_paths``: agent -> points,
dashed) when set; obstacles grey; walls black. A robot out of the episode is drawn faint where it ended.
:func:`draw_state` draws from plain numbers (what a record holds, ``pathplan_env.records.multi``),
:func:`draw` from a live env through it: the same calls, so a replay is the same pixels.
"""

from __future__ import annotations

import numpy as np


def draw_state(scene, obstacle_state, robot_xy, gone, trails, plans, caption: str | None = None, size_px: int = 480) -> np.ndarray:
    """A frame of ``scene`` (a ``MultiScenario``): obstacles at ``obstacle_state`` (N, 4), robot ``i`` at
    ``robot_xy[i]``, faint if ``gone[i]``, its path so far ``trails[i]`` ((k, 2) points) and its plan
    ``plans[i]`` (points, or None)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    world = scene.robot_scenario(0)  # the shared world as the env's MultiWorld builds it
    xmin, ymin, xmax, ymax = scene.world.bounds
    fig = Figure(figsize=(size_px / 100, size_px / 100 * (ymax - ymin) / (xmax - xmin)), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal")
    ax.axis("off")
    for x0, y0, x1, y1, half in world.static_segments:
        ax.plot([x0, x1], [y0, y1], color="black", linewidth=max(1.0, 2 * half * size_px / (xmax - xmin)), solid_capstyle="round")
    for (x, y, _, _), r in zip(obstacle_state, world.arrays()["radii"]):
        ax.add_patch(Circle((x, y), r, color="0.6"))
    colours = matplotlib.colormaps["tab10" if scene.n_robots <= 10 else "tab20"]
    for i in range(scene.n_robots):
        robot = scene.robot_scenario(i)
        colour = colours(i % colours.N)
        trail = np.asarray(trails[i])
        ax.plot(trail[:, 0], trail[:, 1], color=colour, linewidth=1.0, alpha=0.5)
        gx, gy = robot.goal
        ax.plot([gx], [gy], marker="x", color=colour, markersize=6)
        ax.add_patch(Circle(tuple(robot_xy[i]), robot.robot_radius, color=colour, alpha=0.35 if gone[i] else 1.0))
        if plans[i] is not None and not gone[i]:
            path = np.asarray(plans[i])
            ax.plot(path[:, 0], path[:, 1], color=colour, linewidth=1.0, linestyle="--")
    if caption:
        ax.text(xmin + 0.02 * (xmax - xmin), ymax - 0.05 * (ymax - ymin), caption, fontsize=9)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()


def draw(env, size_px: int = 480) -> np.ndarray:
    """The env's current state (its robots' trails, ``env.planned_paths`` and ``env.caption`` if set)."""
    multi = env.multi
    plans = getattr(env, "planned_paths", None) or {}
    return draw_state(env.scene, multi.obstacle_state, [r.xy for r in multi.robots], [a not in env.agents for a in env.possible_agents],
                      env._trails, [plans.get(a) for a in env.possible_agents], getattr(env, "caption", None), size_px)  # fmt: skip


__all__ = ["draw", "draw_state"]
