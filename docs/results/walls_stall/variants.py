import agents


def _v(name, **kw):
    def f(env, seed=None):
        return agents.make(name, env, seed=seed, **kw)

    return f


abc_nostall = _v("abc-spacetime", stall=0)
abc_penalty = _v("abc-spacetime", constraint="penalty")
abc_contacts = _v("abc-spacetime", violation="contacts", constraint="penalty", stall=0)  # the pre-issue-22 defaults
pso_contacts = _v("pso-spacetime", violation="contacts", constraint="penalty", stall=0)


def _bend_rule(optimizer, population=None):
    """A finer rule (a probe, not the shipped one): no early exit only where the cost-to-go's route
    is more than 5 % longer than the straight line from the robot to the goal (it bends round walls
    or resting discs); the early exit elsewhere, walls or not."""
    import math

    from agents.planners.costtogo import distance_to_goal
    from agents.planners.spacetime.metaheuristic_agent import SpacetimeMetaheuristicAgent

    class BendRule(SpacetimeMetaheuristicAgent):
        def plan(self, obs, memory):
            problem = self.timed_problem(obs, memory)
            (x, y), (gx, gy) = problem.robot, problem.goal
            straight = max(math.hypot(gx - x, gy - y) - self.facts.goal_radius, 0.0)
            bends = distance_to_goal(problem.cost_to_go, x, y, gx, gy, self.facts.goal_radius) > 1.05 * straight + 1e-9
            k = self.n_waypoints
            best = self.run_optimizer(problem, self._timed_lo, self._timed_hi, memory, self.seed_paths(problem.robot, problem.goal, problem),
                                      stall=0 if bends else None)  # fmt: skip
            path = np.vstack([problem.robot, best[: 2 * k].reshape(-1, 2), problem.goal])
            self.last_plan = path
            _, px, py = walk_along(path, 0, x, y, best[2 * k] * self.step_length)
            return np.array([px, py])

    def make(env, seed=None):
        kwargs = {} if population is None else {"population": population}
        return BendRule(env, seed, optimizer=optimizer, **kwargs)

    return make


import numpy as np  # noqa: E402

from agents.planners.objective import walk_along  # noqa: E402

abc_bend = _bend_rule("abc", population=40)
pso_bend = _bend_rule("pso")
