"""A trained SB3 ``MlpPolicy`` (Gaussian actions, tanh MLP) evaluated with numpy: no torch needed.

``export_policy`` writes the actor's weights from a stable-baselines3 ``.zip`` to an ``.npz``
beside it; :class:`NumpyPolicy` computes the same actions as ``model.predict`` (the mean when
deterministic, within 1e-5 of SB3's: tested), so the main evaluation runs on a core install.
Written by hand because the forward pass is three matrix products and torch is a multi-GB
dependency for them. A family with an encoder in front of the MLP subclasses it
(``agents.rl.lidar.numpy_encoder.NumpyLidarPolicy``, ``agents.rl.obstacle_set.numpy_net.NumpySetPolicy``);
``agents.rl.export.export_any_policy`` picks the exporter by the model's features extractor.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pathplan_env import _moved

__getattr__ = _moved.names_of(__name__)  # the names of 0.1.0 that live elsewhere now

_ACTIVATIONS = {"Tanh": np.tanh, "ReLU": lambda x: np.maximum(x, 0.0)}
#: A key an encoder family writes -> the class that runs it (named, not imported: no family below here)
_ENCODER_KEYS = {"encoder_layers": "agents.rl.lidar.numpy_encoder.NumpyLidarPolicy", "set_n_tokens": "agents.rl.obstacle_set.numpy_net.NumpySetPolicy"}


class NumpyPolicy:
    """The actor of an exported policy: ``predict(features, deterministic, rng) -> actions``.

    A family with an encoder subclasses it with ``encoder_key`` (a key its export writes),
    ``encoder_kind`` (for the error when it is missing) and :meth:`encoder_of`.
    """

    encoder_key: str | None = None
    encoder_kind = ""

    def encoder_of(self, data):
        """The numpy encoder in front of the MLP, built from the export's arrays (none here)."""
        return None

    def __init__(self, path: str | Path):
        with np.load(path) as data:
            n_layers = int(data["n_layers"])
            self.weights = [data[f"w{i}"] for i in range(n_layers)]  # float32, (in, out)
            self.biases = [data[f"b{i}"] for i in range(n_layers)]
            self.log_std = data["log_std"]
            self.low, self.high = data["action_low"], data["action_high"]
            self.activation = _ACTIVATIONS[str(data["activation"])]
            self.observation_size = int(data["observation_size"])
            family = next((cls for key, cls in _ENCODER_KEYS.items() if key in data), None)
            if family is not None and f"{type(self).__module__}.{type(self).__qualname__}" != family:
                raise ValueError(f"path: {path} holds an encoder in front of the MLP: load it with {family}")
            if self.encoder_key is not None and self.encoder_key not in data:
                raise ValueError(f"path: {path} holds no {self.encoder_kind} encoder (export a PPO trained with --observation {self.encoder_kind})")
            self.encoder = self.encoder_of(data)

    def mean(self, features: np.ndarray) -> np.ndarray:
        x = np.asarray(features, dtype=np.float32)
        if self.encoder is not None:
            x = self.encoder(x)
        for i, (w, b) in enumerate(zip(self.weights, self.biases)):
            x = x @ w + b
            if i < len(self.weights) - 1:  # the last layer is the action head: no activation
                x = self.activation(x)
        return x

    def predict(self, features: np.ndarray, deterministic: bool = True, rng: np.random.Generator | None = None) -> np.ndarray:
        actions = self.mean(features)
        if not deterministic:
            rng = rng if rng is not None else np.random.default_rng()
            actions = actions + np.exp(self.log_std) * rng.standard_normal(actions.shape).astype(np.float32)
        return np.clip(actions, self.low, self.high)  # as SB3 does for a Box action space


def export_policy(model, path: str | Path) -> Path:
    """Write ``model``'s (an SB3 PPO with an ``MlpPolicy`` on flat features) actor to ``path`` (``.npz``).
    A model with an encoder exports with its family's exporter (``agents.rl.export.export_any_policy``)."""
    from stable_baselines3.common.torch_layers import FlattenExtractor

    if not isinstance(model.policy.features_extractor, FlattenExtractor):
        raise ValueError(f"model: {type(model.policy.features_extractor).__name__} is not flat: export it with agents.rl.export.export_any_policy")
    return write_actor(model, path, {})


def write_actor(model, path: str | Path, encoder: dict) -> Path:
    """Write ``model``'s MLP actor head and the ``encoder``'s exported arrays to ``path`` (``.npz``):
    every exporter's last step (:func:`export_policy`, ``agents.rl.obstacle_set.numpy_net.export_set_policy``)."""
    import torch

    policy = model.policy
    layers = [m for m in policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)] + [policy.action_net]
    activations = {type(m).__name__ for m in policy.mlp_extractor.policy_net if not isinstance(m, torch.nn.Linear)}
    if len(activations) != 1 or next(iter(activations)) not in _ACTIVATIONS:
        raise ValueError(f"model: only MLPs with one of {sorted(_ACTIVATIONS)} activations export, got {sorted(activations)}")
    arrays = {f"w{i}": layer.weight.detach().cpu().numpy().T.astype(np.float32) for i, layer in enumerate(layers)}
    arrays |= {f"b{i}": layer.bias.detach().cpu().numpy().astype(np.float32) for i, layer in enumerate(layers)}
    path = Path(path)
    np.savez_compressed(
        path, **arrays, **encoder, n_layers=len(layers), activation=next(iter(activations)),
        log_std=policy.log_std.detach().cpu().numpy().astype(np.float32),
        action_low=model.action_space.low, action_high=model.action_space.high,
        observation_size=model.observation_space.shape[0],
    )  # fmt: skip
    return path
