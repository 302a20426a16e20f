"""Behaviour cloning: fit an SB3 actor-critic policy's mean action and value to demonstrations."""

from __future__ import annotations

import torch

from agents.rl.training.demonstrations import Demonstrations


def behaviour_cloning(
    policy, demonstrations: Demonstrations, epochs: int, seed: int, learning_rate: float = 1e-3, batch_size: int = 256,
    value_weight: float = 0.5, verbose: bool = True,
) -> list[float]:  # fmt: skip
    """Regress ``policy``'s mean action on the demonstrated actions and its value on their discounted
    returns (mean squared errors, the value's weighted by ``value_weight``), with Adam over shuffled
    minibatches. Returns each epoch's mean loss.

    :param policy: an SB3 ``ActorCriticPolicy`` with a Gaussian action distribution (PPO's ``model.policy``).
    :param seed: the minibatch order's seed.
    :param verbose: print the first and last epochs' losses.
    """
    if len(demonstrations) == 0:
        raise ValueError(f"demonstrations: none to clone ({demonstrations.kept} of {demonstrations.episodes} teacher episodes succeeded)")
    obs = torch.as_tensor(demonstrations.features)
    act = torch.as_tensor(demonstrations.actions)
    ret = torch.as_tensor(demonstrations.returns)
    optimizer = torch.optim.Adam(policy.parameters(), lr=learning_rate)
    generator = torch.Generator().manual_seed(seed)
    policy.set_training_mode(True)
    losses = []
    for epoch in range(epochs):
        order = torch.randperm(len(obs), generator=generator)
        total = 0.0
        for start in range(0, len(obs), batch_size):
            idx = order[start : start + batch_size]
            distribution = policy.get_distribution(obs[idx])
            values = policy.predict_values(obs[idx]).squeeze(-1)
            loss = torch.nn.functional.mse_loss(distribution.distribution.mean, act[idx]) + value_weight * torch.nn.functional.mse_loss(values, ret[idx])
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            total += float(loss.detach()) * len(idx)
        losses.append(total / len(obs))
        if verbose and epoch in (0, epochs - 1):
            print(f"behaviour cloning epoch {epoch + 1}/{epochs}: loss {losses[-1]:.4f}")
    policy.set_training_mode(False)
    return losses
