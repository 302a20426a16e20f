"""A frame of the multi-robot env (``render_mode="rgb_array"``): matplotlib off-screen (Agg), no display.

Robots in colour with their trails, goals (crosses) and plans (``env.planned_paths``: agent -> points,
dashed) when set; obstacles grey; walls black. A robot out of the episode is drawn faint where it ended.
"""

from __future__ import annotations

import numpy as np


def draw(env, size_px: int = 480) -> np.ndarray:
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    multi, scene = env.multi, env.scene
    xmin, ymin, xmax, ymax = scene.world.bounds
    fig = Figure(figsize=(size_px / 100, size_px / 100 * (ymax - ymin) / (xmax - xmin)), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal")
    ax.axis("off")
    for x0, y0, x1, y1, half in multi.world.static_segments:
        ax.plot([x0, x1], [y0, y1], color="black", linewidth=max(1.0, 2 * half * size_px / (xmax - xmin)), solid_capstyle="round")
    for (x, y, _, _), r in zip(multi.obstacle_state, multi.world.radii):
        ax.add_patch(Circle((x, y), r, color="0.6"))
    colours = matplotlib.colormaps["tab10" if scene.n_robots <= 10 else "tab20"]
    plans = getattr(env, "planned_paths", None) or {}
    for i, (agent, robot) in enumerate(zip(env.possible_agents, multi.robots)):
        colour = colours(i % colours.N)
        gone = agent not in env.agents
        trail = np.array(env._trails[i])
        ax.plot(trail[:, 0], trail[:, 1], color=colour, linewidth=1.0, alpha=0.5)
        gx, gy = scene.robot_scenario(i).goal
        ax.plot([gx], [gy], marker="x", color=colour, markersize=6)
        ax.add_patch(Circle(robot.xy, multi.radii[i], color=colour, alpha=0.35 if gone else 1.0))
        if agent in plans and plans[agent] is not None and not gone:
            path = np.asarray(plans[agent])
            ax.plot(path[:, 0], path[:, 1], color=colour, linewidth=1.0, linestyle="--")
    caption = getattr(env, "caption", None)
    if caption:
        ax.text(xmin + 0.02 * (xmax - xmin), ymax - 0.05 * (ymax - ymin), caption, fontsize=9)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()


__all__ = ["draw"]
