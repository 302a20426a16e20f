"""SARL's value network in torch (training only; :mod:`agents.rl.sarl.numpy_net` runs it without torch).

Chen et al. 2019 (CrowdNav's ``sarl.py``): every human's joint state (the robot's own state in its
goal frame beside that human's relative state) goes through ``mlp1``; the mean of those embeddings
over the present humans is the crowd context; ``attention`` scores [embedding, context]; the softmax
of the scores over the present humans weights ``mlp2``'s features; the weighted sum beside the
robot's own state goes through ``mlp3`` to one value. Absent humans (padding rows, ``mask`` 0) get a
finite -1e9 score (not -inf: a scene with no human keeps finite numbers) and a zero weight.
"""

from __future__ import annotations

import torch
from torch import nn

from agents.rl.sarl.numpy_net import HIDDEN, HUMAN_DIM, MASK_FILL, SELF_DIM, check_sizes


def _mlp(sizes: list[int], last_relu: bool) -> nn.Sequential:
    layers: list[nn.Module] = []
    for i in range(len(sizes) - 1):
        layers.append(nn.Linear(sizes[i], sizes[i + 1]))
        if i < len(sizes) - 2 or last_relu:
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


class SARLValue(nn.Module):
    """``forward(self_state (B, 5), humans (B, N, 7), mask (B, N)) -> values (B,)``.

    :param hidden: the hidden sizes of ``mlp1``, ``mlp2``, ``attention`` and ``mlp3`` (default
        ``agents.rl.sarl.numpy_net.HIDDEN``, smaller than CrowdNav's).
    :param dims: ``(self_dim, human_dim)``, the joint state's widths (``SARLFeatures.dims``; CrowdNav's by default).
    """

    def __init__(self, hidden: dict[str, tuple[int, ...]] | None = None, dims: tuple[int, int] = (SELF_DIM, HUMAN_DIM)):
        super().__init__()
        self.hidden = check_sizes(hidden if hidden is not None else HIDDEN)
        h = self.hidden
        self.self_dim, human_dim = dims
        self.mlp1 = _mlp([self.self_dim + human_dim, *h["mlp1"]], last_relu=True)
        self.mlp2 = _mlp([h["mlp1"][-1], *h["mlp2"]], last_relu=False)
        self.attention = _mlp([2 * h["mlp1"][-1], *h["attention"], 1], last_relu=False)
        self.mlp3 = _mlp([self.self_dim + h["mlp2"][-1], *h["mlp3"], 1], last_relu=False)

    def forward(self, self_state: torch.Tensor, humans: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
        b, n, _ = humans.shape
        joint = torch.cat([self_state[:, None, :].expand(b, n, self.self_dim), humans], dim=-1)
        embedding = self.mlp1(joint)
        m = mask[..., None]
        context = (embedding * m).sum(1) / m.sum(1).clamp(min=1.0)
        scores = self.attention(torch.cat([embedding, context[:, None, :].expand_as(embedding)], dim=-1))[..., 0]
        scores = torch.where(mask > 0, scores, torch.full_like(scores, MASK_FILL))
        weights = torch.softmax(scores, dim=1) * mask
        crowd = (weights[..., None] * self.mlp2(embedding)).sum(1)
        return self.mlp3(torch.cat([self_state, crowd], dim=-1))[..., 0]

    def export(self) -> dict:
        """The weights as numpy arrays, ``{"<mlp>.w<i>": (in, out), "<mlp>.b<i>": (out,)}`` (``SARLNumpy``'s input)."""
        arrays = {}
        for name in ("mlp1", "mlp2", "attention", "mlp3"):
            linears = [m for m in getattr(self, name) if isinstance(m, nn.Linear)]
            for i, layer in enumerate(linears):
                arrays[f"{name}.w{i}"] = layer.weight.detach().cpu().numpy().T.copy()
                arrays[f"{name}.b{i}"] = layer.bias.detach().cpu().numpy().copy()
        return arrays
