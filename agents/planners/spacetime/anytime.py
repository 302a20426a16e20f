"""Which plan a space-time A* that ran out of budget acts on: the anytime half of ``astar-spacetime``.

:func:`agents.planners.spacetime.astar.search` stops when its work or expansions budget runs out,
and returns every node it generated (:class:`~agents.planners.spacetime.astar.SearchTree`). Each
node's path from the start is free of contact on the prediction, so any of them is a plan the robot
can fly; :func:`partial_plan` picks one by a rule chosen by name (:data:`PARTIAL_RULES`):

* ``"deepest"``: the node that survives longest on the prediction, nearer the goal on ties (what
  the search itself returns, and what the clairvoyant oracle flies after a failed search);
* ``"progress"``: of the nodes that survive at least ``min_steps`` steps (or, when none does, as
  long as the deepest), the one with the fewest steps still to go, deeper on ties. A plan that
  wanders away from the goal is then never chosen over one that survives as long and gains ground.

Ties go to the node generated first, so the choice is as deterministic as the search.
"""

from __future__ import annotations

import numpy as np

from agents.planners.spacetime.astar import SearchTree

#: The rules :func:`partial_plan` knows.
PARTIAL_RULES = ("deepest", "progress")


def partial_plan(tree: SearchTree | list[SearchTree], rule: str = "progress", min_steps: int = 5) -> np.ndarray:
    """The waypoints (steps, 2) of the node ``rule`` picks from ``tree`` (or from several searches'
    trees of one problem, as one); empty when there is only the root (no move is free of contact)."""
    if rule not in PARTIAL_RULES:
        raise ValueError(f"rule must be one of {PARTIAL_RULES}, got {rule!r}")
    tree = tree if isinstance(tree, SearchTree) else merged(tree)
    depth = tree.k
    if depth.max(initial=0) == 0:
        return np.empty((0, 2))
    if rule == "deepest":
        candidates = np.flatnonzero(depth == depth.max())
    else:
        candidates = np.flatnonzero(depth >= min(int(depth.max()), int(min_steps)))
    # lexsort's last key sorts first: fewest steps to go, then deepest, then first generated
    best = candidates[np.lexsort((candidates, -depth[candidates], tree.h[candidates]))[0]]
    return path_to(tree, int(best))


def merged(trees: list[SearchTree]) -> SearchTree:
    """Several trees as one (each one's parents offset by the nodes before it), in the given order."""
    offsets = np.cumsum([0] + [len(t.k) for t in trees[:-1]])
    parents = [np.where(t.parent >= 0, t.parent + offset, -1) for t, offset in zip(trees, offsets)]
    columns = {name: np.concatenate([getattr(t, name) for t in trees]) for name in SearchTree._fields if name != "parent"}
    return SearchTree(parent=np.concatenate(parents), **columns)


def path_to(tree: SearchTree, node: int) -> np.ndarray:
    """The waypoints (one a step) from the root to ``node``."""
    steps = int(tree.k[node])
    targets = np.empty((steps, 2))
    for s in range(steps - 1, -1, -1):
        targets[s] = tree.tx[node], tree.ty[node]
        node = int(tree.parent[node])
    return targets
