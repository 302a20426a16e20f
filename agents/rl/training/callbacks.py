"""SB3 callbacks of a training run: the Δd curriculum, and validation on the same episodes every time."""

from __future__ import annotations

import time

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback, EvalCallback
from stable_baselines3.common.evaluation import evaluate_policy


class DeltaDCurriculum(BaseCallback):
    """Widen the training episodes' Δd range linearly from ``[0, start]`` to ``[0, end]`` over the first
    ``horizon`` env steps; the training envs are ``EpisodeSchedule``\\ s (``set_delta_d``).

    :param every: vector steps between updates of the envs' range (and of TensorBoard's ``curriculum/delta_d_max``).
    """

    def __init__(self, start: float, end: float, horizon: float, every: int = 64, verbose: int = 0):
        super().__init__(verbose)
        self.start, self.end, self.horizon, self.every = start, end, max(1.0, horizon), every

    def delta_d_max(self, num_timesteps: int) -> float:
        """The top of the Δd range after ``num_timesteps`` env steps."""
        return self.start + (self.end - self.start) * min(1.0, num_timesteps / self.horizon)

    def _on_step(self) -> bool:
        if self.n_calls % self.every == 1:
            high = self.delta_d_max(self.num_timesteps)
            self.training_env.env_method("set_delta_d", (0.0, high))
            self.logger.record("curriculum/delta_d_max", high)
        return True


class WallClockBudget(BaseCallback):
    """Stop training once ``seconds`` have passed since ``start`` (a ``time.perf_counter()`` reading
    taken before the warm start, so the budget covers demonstrations, cloning and RL)."""

    def __init__(self, start: float, seconds: float, verbose: int = 0):
        super().__init__(verbose)
        self.start, self.seconds = start, seconds

    def _on_step(self) -> bool:
        if time.perf_counter() - self.start < self.seconds:
            return True
        print(f"wall-clock budget of {self.seconds / 60:g} min reached at {self.num_timesteps} PPO steps: stopping")
        return False


class SameEpisodesEval(EvalCallback):
    """``EvalCallback`` on an ``EpisodeSchedule`` env rewound before every evaluation: each one scores the
    same validation episodes (success rate from ``info["is_success"]``) and the best model is kept."""

    def _on_step(self) -> bool:
        if self.eval_freq > 0 and self.n_calls % self.eval_freq == 0:
            self.eval_env.env_method("restart")
        return super()._on_step()


def validation_success(model, eval_env, episodes: int) -> float:
    """Success rate of ``model``'s mean actions on the validation episodes (``eval_env`` rewound first),
    as ``SameEpisodesEval`` measures it."""
    eval_env.env_method("restart")
    successes = []

    def record(local_vars, _globals):
        if local_vars["done"]:
            successes.append(bool(local_vars["info"].get("is_success", False)))

    evaluate_policy(model, eval_env, n_eval_episodes=episodes, deterministic=True, callback=record)
    return float(np.mean(successes))
