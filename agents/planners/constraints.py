"""How the optimisers rank two candidates under the contact constraint, and when they stop early.

Every objective returns ``(cost, penalty)``: the cost includes the penalty (the paper's Eq. 4 on
contact), and a candidate is feasible when its penalty is 0. The rule is chosen by name
(:data:`CONSTRAINTS`) and compiled into the PSO and ABC kernels as a :class:`ConstraintRule`:

* ``"penalty"``: the smaller cost wins (the paper's static penalty; the space-time objective adds a
  feasibility offset to every contact, so it is Deb's first rule in penalty form).
* ``"deb"``: Deb's feasibility rules (Deb 2000): a feasible candidate beats an infeasible one;
  between two infeasible ones the smaller violation (penalty) wins; between two feasible ones the
  smaller cost.
* ``"adaptive"``: the cost with its penalty scaled by ``lam`` (Hadj-Alouane and Bean 1997):
  ``cost + (lam - 1) * penalty``; ``lam`` grows by ``grow`` after ``window`` iterations whose best
  was infeasible and shrinks by ``shrink`` after ``window`` whose best was feasible.

``stall``: stop the run once the best is feasible and has not improved by more than ``tolerance``
(m) for ``stall`` iterations (PSO) or cycles (ABC); 0 runs the whole budget.
"""

from __future__ import annotations

from typing import NamedTuple

import numba

PENALTY, DEB, ADAPTIVE = 0, 1, 2
#: The constraint rules by name.
CONSTRAINTS = {"penalty": PENALTY, "deb": DEB, "adaptive": ADAPTIVE}


class ConstraintRule(NamedTuple):
    """The ranking rule and the early exit, as the compiled optimisers read them."""

    kind: int = PENALTY  # PENALTY, DEB or ADAPTIVE
    start: float = 1.0  # adaptive: the penalty's first scale
    grow: float = 2.0  # adaptive: scale x grow after ``window`` infeasible bests
    shrink: float = 0.5  # adaptive: scale x shrink after ``window`` feasible bests
    window: int = 3  # adaptive: iterations (cycles) between changes of the scale
    stall: int = 0  # stop once the best is feasible and unchanged for this many iterations (0: never)
    tolerance: float = 1e-3  # m: a smaller improvement counts as unchanged


def constraint_rule(constraint: str = "penalty", stall: int = 0, **adaptive) -> ConstraintRule:
    """The record for a rule given by name; bad values raise ``ValueError`` naming the field."""
    if constraint not in CONSTRAINTS:
        raise ValueError(f"constraint must be one of {sorted(CONSTRAINTS)}, got {constraint!r}")
    if int(stall) != stall or stall < 0:
        raise ValueError(f"stall must be a non-negative integer, got {stall!r}")
    rule = ConstraintRule(CONSTRAINTS[constraint], stall=int(stall))._replace(**adaptive)
    if not (rule.start > 0 and rule.grow >= 1 and 0 < rule.shrink <= 1 and rule.window >= 1):
        raise ValueError(f"the adaptive penalty needs start > 0, grow >= 1, 0 < shrink <= 1, window >= 1, got {adaptive!r}")
    return rule


@numba.njit(cache=True, inline="always", error_model="numpy")
def better(cost_a, pen_a, cost_b, pen_b, kind, lam):
    """Whether candidate a ``(cost_a, pen_a)`` ranks strictly before b under the rule ``kind``."""
    if kind == DEB:
        if pen_a == 0.0 and pen_b == 0.0:
            return cost_a < cost_b
        if pen_a == 0.0 or pen_b == 0.0:
            return pen_a == 0.0
        return pen_a < pen_b
    if kind == ADAPTIVE:
        return cost_a + (lam - 1.0) * pen_a < cost_b + (lam - 1.0) * pen_b
    return cost_a < cost_b


@numba.njit(cache=True, inline="always", error_model="numpy")
def score(cost, pen, kind, lam):
    """A candidate's cost as the rule sees it (the ABC's roulette weighs ``1 / (1 + score)``)."""
    if kind == ADAPTIVE:
        return cost + (lam - 1.0) * pen
    return cost


@numba.njit(cache=True, inline="always", error_model="numpy")
def adapt(lam, infeasible_run, feasible_run, best_pen, rule):
    """One iteration's update of the adaptive scale: ``(lam, infeasible_run, feasible_run)``."""
    if best_pen > 0.0:
        infeasible_run, feasible_run = infeasible_run + 1, 0
    else:
        infeasible_run, feasible_run = 0, feasible_run + 1
    if rule.kind == ADAPTIVE:
        if infeasible_run >= rule.window:
            lam, infeasible_run = lam * rule.grow, 0
        elif feasible_run >= rule.window:
            lam, feasible_run = lam * rule.shrink, 0
    return lam, infeasible_run, feasible_run


@numba.njit(cache=True, inline="always", error_model="numpy")
def stalled(rule, best_pen, improvement, unchanged):
    """The early exit's count after one iteration, and whether to stop: ``(unchanged, stop)``."""
    if best_pen > 0.0 or improvement > rule.tolerance:
        return 0, False
    unchanged += 1
    return unchanged, rule.stall > 0 and unchanged >= rule.stall
