"""A set encoder over the obstacles for SB3 policies: SARL's attention pooling, or DeepSets' mean (torch).

:class:`SetAttentionExtractor` reads :mod:`agents.rl.obstacle_set.features`' flat ``Box``. Each obstacle
token, concatenated with the ego token, goes through a shared MLP (``φ``, ReLU) to an embedding
``e_i``; SARL's attention scores each ``e_i`` together with the masked mean of all of them (the
crowd's context) by a small MLP, padding slots get the finite logit ``MASK_FILL``, the softmax
weights (times the mask, so an empty set pools to zero) average ``ψ(e_i)``. With
``pooling="mean"`` the weights are the mask's uniform ones (DeepSets). The output is the ego
token and the pooled vector; SB3's usual policy and value MLPs follow. The tokens are
distance-sorted, but no layer reads a slot's index, so the output is invariant to the obstacles'
order (tested).

From rl-zoo3 (or any SB3 script), on an env wrapped in ``agents.rl.obstacle_set.features.SetLearningEnv``::

    from agents.rl.obstacle_set.encoder import SetAttentionExtractor
    PPO("MlpPolicy", env, policy_kwargs=dict(features_extractor_class=SetAttentionExtractor,
                                             features_extractor_kwargs=dict(hidden="64,64", pooling="attention")))

``agents.rl.obstacle_set.numpy_net`` computes the same forward pass in numpy (tested equal within 1e-5).
"""

from __future__ import annotations

import gymnasium as gym
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn

from agents.rl.obstacle_set.features import EGO_SIZE, MASK_FILL, POOLINGS, TOKEN_SIZE, check_pooling, parse_hidden, tokens_of


def _mlp(sizes: list[int], last_relu: bool = True) -> nn.Sequential:
    layers = []
    for i, (a, b) in enumerate(zip(sizes, sizes[1:])):
        layers.append(nn.Linear(a, b))
        if last_relu or i < len(sizes) - 2:
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


class SetAttentionExtractor(BaseFeaturesExtractor):
    """Permutation-invariant encoder of the obstacle tokens, concatenated with the ego token.

    :param observation_space: a flat ``Box`` of ``set_features`` (its size fixes the token count).
    :param hidden: widths of the embedding MLP ``φ`` (its input is a token and the ego token); the
        last is the pooled width, and the attention scorer's hidden width is the first.
    :param pooling: ``"attention"`` (SARL's) or ``"mean"`` (DeepSets' masked mean).
    """

    def __init__(self, observation_space: gym.spaces.Box, hidden: str = "64,64", pooling: str = "attention"):
        widths, pooling = parse_hidden(hidden), check_pooling(pooling)
        if len(observation_space.shape) != 1:
            raise ValueError(f"observation_space: expected a flat Box of set features, got shape {observation_space.shape}")
        n_tokens = tokens_of(observation_space.shape[0])
        super().__init__(observation_space, features_dim=EGO_SIZE + widths[-1])
        self.n_tokens, self.pooling = n_tokens, pooling
        self.embed = _mlp([TOKEN_SIZE + EGO_SIZE] + widths)
        self.value = _mlp([widths[-1], widths[-1]])
        self.score = _mlp([2 * widths[-1], widths[0], 1], last_relu=False) if pooling == "attention" else None

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        n = self.n_tokens
        tokens = observations[:, : n * TOKEN_SIZE].reshape(-1, n, TOKEN_SIZE)
        mask = observations[:, n * TOKEN_SIZE : n * (TOKEN_SIZE + 1)]
        ego = observations[:, n * (TOKEN_SIZE + 1) :]
        embedded = self.embed(torch.cat([tokens, ego[:, None, :].expand(-1, n, -1)], dim=-1))  # (B, n, h)
        count = mask.sum(dim=1, keepdim=True).clamp(min=1.0)
        if self.score is None:
            weights = mask / count
        else:
            context = (embedded * mask[..., None]).sum(dim=1) / count  # the crowd: masked mean
            logits = self.score(torch.cat([embedded, context[:, None, :].expand(-1, n, -1)], dim=-1))[..., 0]
            logits = torch.where(mask > 0, logits, torch.full_like(logits, MASK_FILL))
            weights = torch.softmax(logits, dim=1) * mask
        pooled = (weights[..., None] * self.value(embedded)).sum(dim=1)
        return torch.cat([ego, pooled], dim=1)


__all__ = ["POOLINGS", "SetAttentionExtractor", "check_pooling", "parse_hidden"]
