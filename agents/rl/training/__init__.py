"""Training a policy for DynamicObstacle-v0 with stable-baselines3 (``scripts/train_rl.py`` is its command line).

- ``config``: :class:`Args`, the run's arguments (PPO defaults from ``pathplan_env.zoo.PPO_SETTINGS``);
- ``demonstrations``: a planner's successful episodes as labelled steps (:func:`collect_demonstrations`);
- ``cloning``: :func:`behaviour_cloning` of those into the policy's mean action and value (torch);
- ``callbacks``: the Δd curriculum and validation on the same episodes (SB3);
- ``outputs``: learning curve, metadata sidecars (with ``agents.provenance.versions()``), shipping;
- ``run``: the envs, the model and :func:`train`.

Importing this package needs no torch or stable-baselines3: ``cloning`` and ``callbacks``, which do,
are imported when a run starts.

    from agents.rl.training import Args, train
    meta = train(Args(total_timesteps=100_000, eval_freq=50_000, out="runs/quick"))
"""

from agents.rl.training.config import Args, dataclass_parser, field_docs, parse_dataclass
from agents.rl.training.demonstrations import Demonstrations, collect_demonstrations, discounted_returns
from agents.rl.training.outputs import learning_curve, run_metadata, ship, write_sidecars
from agents.rl.training.run import build_model, demonstration_env, make_env, train

__all__ = [
    "Args", "Demonstrations", "build_model", "collect_demonstrations", "demonstration_env", "dataclass_parser", "discounted_returns", "field_docs",
    "learning_curve", "make_env", "parse_dataclass", "run_metadata", "ship", "train", "write_sidecars",
]  # fmt: skip
