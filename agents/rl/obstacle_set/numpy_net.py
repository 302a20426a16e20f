"""The set encoder (``agents.rl.obstacle_set.encoder.SetAttentionExtractor``) and its PPO actor in numpy: no torch needed.

The same forward pass as torch's: the shared token MLP, SARL's attention (or the masked mean) with
the finite ``MASK_FILL`` on padding slots, ``ψ``, the weighted sum, the ego token in front, then the
policy MLP of :class:`agents.rl.numpy_policy.NumpyPolicy`. Equal to torch within 1e-5 (tested,
padded slots included). Hand-written for the reason ``numpy_policy`` is: a few matrix products,
and torch is a multi-GB dependency for them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from agents.rl.numpy_policy import NumpyPolicy, write_actor
from agents.rl.obstacle_set.features import EGO_SIZE, MASK_FILL, POOLINGS, TOKEN_SIZE

#: The ``.npz`` keys of an exported set encoder start with this.
PREFIX = "set_"


def _linears(sequential) -> list:
    import torch

    return [m for m in sequential if isinstance(m, torch.nn.Linear)]


def _mlp(x: np.ndarray, layers: list[tuple[np.ndarray, np.ndarray]], last_relu: bool = True) -> np.ndarray:
    for i, (w, b) in enumerate(layers):
        x = x @ w + b
        if last_relu or i < len(layers) - 1:
            x = np.maximum(x, 0.0)
    return x


class NumpySetEncoder:
    """The features extractor's forward pass from an exported ``.npz`` (:func:`export_set_encoder`'s keys)."""

    def __init__(self, data):
        self.n_tokens = int(data[PREFIX + "n_tokens"])
        self.pooling = POOLINGS[int(data[PREFIX + "pooling"])]

        def layers(name):
            return [(data[f"{PREFIX}{name}_w{i}"], data[f"{PREFIX}{name}_b{i}"]) for i in range(int(data[f"{PREFIX}{name}_layers"]))]

        self.embed, self.value = layers("embed"), layers("value")
        self.score = layers("score") if self.pooling == "attention" else None

    def __call__(self, features: np.ndarray) -> np.ndarray:
        x = np.asarray(features, np.float32)
        single = x.ndim == 1
        x = np.atleast_2d(x)
        n = self.n_tokens
        tokens = x[:, : n * TOKEN_SIZE].reshape(len(x), n, TOKEN_SIZE)
        mask = x[:, n * TOKEN_SIZE : n * (TOKEN_SIZE + 1)]
        ego = x[:, n * (TOKEN_SIZE + 1) :]
        embedded = _mlp(np.concatenate([tokens, np.broadcast_to(ego[:, None, :], (len(x), n, EGO_SIZE))], axis=-1), self.embed)
        count = np.maximum(mask.sum(axis=1, keepdims=True), 1.0)
        if self.score is None:
            weights = mask / count
        else:
            context = (embedded * mask[..., None]).sum(axis=1) / count
            both = np.concatenate([embedded, np.broadcast_to(context[:, None, :], embedded.shape)], axis=-1)
            logits = np.where(mask > 0, _mlp(both, self.score, last_relu=False)[..., 0], np.float32(MASK_FILL))
            weights = np.exp(logits - logits.max(axis=1, keepdims=True))
            weights = weights / weights.sum(axis=1, keepdims=True) * mask
        pooled = (weights[..., None] * _mlp(embedded, self.value)).sum(axis=1)
        out = np.concatenate([ego, pooled], axis=1).astype(np.float32)
        return out[0] if single else out


def export_set_encoder(extractor) -> dict[str, np.ndarray]:
    """The arrays of a ``SetAttentionExtractor`` (torch) as :class:`NumpySetEncoder` reads them."""
    arrays = {PREFIX + "n_tokens": np.array(extractor.n_tokens), PREFIX + "pooling": np.array(POOLINGS.index(extractor.pooling))}
    parts = {"embed": extractor.embed, "value": extractor.value} | ({"score": extractor.score} if extractor.score is not None else {})
    for name, sequential in parts.items():
        linears = _linears(sequential)
        arrays[f"{PREFIX}{name}_layers"] = np.array(len(linears))
        for i, layer in enumerate(linears):
            arrays[f"{PREFIX}{name}_w{i}"] = layer.weight.detach().cpu().numpy().T.astype(np.float32)
            arrays[f"{PREFIX}{name}_b{i}"] = layer.bias.detach().cpu().numpy().astype(np.float32)
    return arrays


class NumpySetPolicy(NumpyPolicy):
    """:class:`NumpyPolicy` whose features go through the exported set encoder first."""

    encoder_key, encoder_kind = PREFIX + "n_tokens", "set"

    def encoder_of(self, data) -> NumpySetEncoder:
        return NumpySetEncoder(data)


def export_set_policy(model, path: str | Path) -> Path:
    """Write ``model``'s (an SB3 PPO whose ``MlpPolicy`` shares a ``SetAttentionExtractor``) actor to
    ``path`` (``.npz``), as :class:`NumpySetPolicy` reads it."""
    from agents.rl.obstacle_set.encoder import SetAttentionExtractor

    policy = model.policy
    if not isinstance(policy.features_extractor, SetAttentionExtractor) or not policy.share_features_extractor:
        raise ValueError(f"model: expected a shared SetAttentionExtractor, got {type(policy.features_extractor).__name__}")
    return write_actor(model, path, export_set_encoder(policy.features_extractor))


__all__ = ["NumpySetEncoder", "NumpySetPolicy", "export_set_encoder", "export_set_policy"]
