"""The harness's progress bar: episodes done, and an estimate of the time left from each cell's own
finished episodes, or none.

tqdm's own estimate extrapolates the recent rate of the whole run; a run's cells differ by a
thousandfold (``straight`` against ``oracle-clairvoyant``), so it swung from hours to minutes as the
cells went by. Here each cell's time left is its mean episode time (the episode's own wall time,
after the agent's warm-up) times its episodes left; the run's is their sum over the workers, shown
once every unfinished cell has finished an episode, and "no estimate yet" until then. The harness
orders its jobs episode by episode across the cells (:func:`interleaved`), so that comes early.
"""

from __future__ import annotations

import sys
from collections import Counter, defaultdict

from tqdm import tqdm

BAR_FORMAT = "{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]"


def cell_of(item) -> tuple | None:
    """The (agent, scenario, Δd) cell of a job or a result (``None``: a job of another shape)."""
    agent, scenario = getattr(item, "agent", None), getattr(item, "scenario", None)
    if agent is None or scenario is None or not hasattr(item, "delta_d"):
        return None
    return (getattr(agent, "label", agent), getattr(scenario, "label", scenario), item.delta_d)


def interleaved(jobs: list) -> list:
    """``jobs`` ordered by episode, then as given: every cell's first episode comes first (a job's
    result does not depend on when it runs)."""
    return sorted(jobs, key=lambda job: getattr(job, "episode", 0))  # stable: within an episode, the given order


def duration_text(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class Progress:
    """A tqdm bar over ``jobs`` whose postfix is the estimate of the module's doc."""

    def __init__(self, jobs: list, workers: int, desc: str = "episodes"):
        self.left = Counter(cell_of(job) for job in jobs)
        self.workers = max(1, int(workers))
        self.seconds: dict[tuple, list[float]] = defaultdict(list)
        self.bar = tqdm(total=len(jobs), desc=desc, file=sys.stderr, bar_format=BAR_FORMAT)
        self.bar.set_postfix_str(self.estimate(), refresh=False)

    def estimate(self) -> str:
        """``", about N min left"``, or ``", no estimate yet"`` while a cell with episodes left has finished none."""
        if None in self.left:
            return ""
        todo = {cell: n for cell, n in self.left.items() if n > 0}
        if not todo:
            return ""
        if any(not self.seconds[cell] for cell in todo):
            return "no estimate yet: each cell's first episode gives one"
        work = sum(n * sum(self.seconds[cell]) / len(self.seconds[cell]) for cell, n in todo.items())
        return f"about {duration_text(work / min(self.workers, sum(todo.values())))} left"

    def update(self, result) -> None:
        cell = cell_of(result)
        if cell in self.left:
            self.left[cell] -= 1
            seconds = getattr(result, "seconds", 0.0)
            if seconds and seconds > 0:
                self.seconds[cell].append(float(seconds))
        self.bar.set_postfix_str(self.estimate(), refresh=False)
        self.bar.update()

    def close(self) -> None:
        self.bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


__all__ = ["Progress", "cell_of", "duration_text", "interleaved"]
