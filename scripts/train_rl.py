"""Train a stable-baselines3 agent (PPO by default, or SAC) on DynamicObstacle-v0.

    python scripts/train_rl.py --total-timesteps 4000000 --seed 0 --out runs/ppo
    python scripts/train_rl.py --algo sac --teacher '' --n-envs 4 --total-timesteps 500000 --out runs/sac
    python scripts/train_rl.py ... --ship best       # also copy the best model to agents/models/<algo>.zip
    python scripts/train_rl.py --observation lidar --scenarios random,doorway,random,cluttered-room,random,corridor,random,intersection
        --teacher-steps 100000 --teacher-epochs 15 --total-timesteps 800000 --eval-freq 50000 --budget-minutes 57 --out runs/ppo_lidar
        (one command: a lidar policy with a 1-D convolution encoder, run by agents.make("ppo-lidar", env))
    python scripts/train_rl.py --observation set --total-timesteps 250000 --teacher-steps 50000 --teacher-epochs 10 --eval-freq 25000
        --out runs/ppo_set   (every obstacle a token, attention pooling: agents.make("ppo-set", env); docs/results/ppo_set.md)

The policy sees ``pathplan_env.wrappers.make_learning_env``'s egocentric features and acts in its
relative-waypoint action space, the same transforms ``agents.make("ppo", env)`` applies at test time.
Training episodes come from ``EpisodeSchedule`` streams of training seeds (disjoint from the
validation and test splits of ``pathplan_env.scenarios.splits``), on random scenes whose Δd widens from
``[0, --delta-d-start]`` to ``[0, --delta-d-max]`` over the first ``--curriculum-fraction`` of training.
An ``EvalCallback`` scores the same validation episodes every ``--eval-freq`` steps (success rate
from ``info["is_success"]``) and keeps the best model. Writes to ``--out``: TensorBoard logs,
checkpoints, ``cloned_model.zip`` (with a ``--teacher``), ``best_model.zip``, ``final_model.zip``, a
sidecar beside each of those three (``best_model.json``, ...: the algorithm, k_nearest, the command,
seed and figures, which ``agents.make("ppo", env, path=...)`` reads), ``evaluations.npz`` and
``learning_curve.png``. The PPO defaults are ``pathplan_env.zoo.PPO_SETTINGS``, which rl-zoo3's
hyperparameters share; the training itself is the library ``agents.rl.training``.

``--observation lidar`` trains on the ``"lidar"`` observation instead (``agents.rl.lidar.features``:
the scan in the goal's frame, min-pooled to ``--lidar-bins``, with its change since the last step;
``agents.rl.lidar.encoder``: stride-2 ``Conv1d`` layers with circular padding), cloned from a teacher
that reads the exact state while a lockstep twin env records what the lidar sees; ``--scenarios``
deals presets (wall families too) to the training envs; ``--budget-minutes`` caps the run's wall time.

``--observation set`` trains on every obstacle as a token (``agents.rl.obstacle_set.features``: goal-frame
position, velocity, radius, gap and positions predicted by the planners' physics, distance-sorted,
masked, with an ego token; ``agents.rl.obstacle_set.encoder``: SARL's attention pooling or, with
``--set-pooling mean``, DeepSets'), cloned from the same teacher; ``--set-tokens`` sets the padding.
"""

from __future__ import annotations

import argparse
import shlex
import sys

from agents.rl.training import Args, dataclass_parser, parse_dataclass, train


def build_parser() -> argparse.ArgumentParser:
    """Flags from the dataclass's fields (``--total-timesteps``, ``--no-progress``, ...), with their docs."""
    return dataclass_parser(Args, __doc__)


def parse_args(argv=None) -> Args:
    return parse_dataclass(Args, build_parser(), argv)


if __name__ == "__main__":
    train(parse_args(), command="python " + " ".join(shlex.quote(a) for a in sys.argv))
