"""SARL's value network (:mod:`agents.rl.sarl_net`) evaluated without torch: the agent acts on a core install.

The forward pass is a few small matrix products over (actions × humans) rows. Each dense layer is a
compiled single-threaded loop (:func:`dense`), not numpy's ``@``: OpenBLAS splits even these small
products over threads, which on a busy 2-core machine took 20-70 ms a forward instead of about 1.
"""

from __future__ import annotations

import numba
import numpy as np

#: The robot's own features (:func:`agents.rl.sarl_lookahead.joint_state`) and each human's, CrowdNav's
#: (a setting with more features, ``SARLFeatures``, has wider inputs: the weights say which).
SELF_DIM, HUMAN_DIM = 5, 7
#: Hidden sizes: CrowdNav's sarl has mlp1 150-100, mlp2 100-50, attention 100-100, mlp3 150-100-100;
#: these are about a quarter of its multiply-adds, so that 81 moves score within a millisecond.
HIDDEN = {"mlp1": (100, 50), "mlp2": (50,), "attention": (50,), "mlp3": (100, 50)}
#: The attention score of an absent human: finite, so a scene without humans stays finite.
MASK_FILL = -1e9


def check_sizes(hidden: dict) -> dict[str, tuple[int, ...]]:
    """``hidden`` validated: the four MLPs by name, each a non-empty list of positive ints."""
    if not isinstance(hidden, dict) or set(hidden) != set(HIDDEN):
        raise ValueError(f"hidden must name exactly {sorted(HIDDEN)}, got {hidden!r}")
    out = {}
    for name, sizes in hidden.items():
        sizes = tuple(sizes)
        if not sizes or any(not isinstance(s, (int, np.integer)) or isinstance(s, bool) or s < 1 for s in sizes):
            raise ValueError(f"hidden[{name!r}] must be positive ints, got {sizes!r}")
        out[name] = tuple(int(s) for s in sizes)
    return out


@numba.njit(cache=True, fastmath=True)
def dense(x, w_t, b, relu):
    """``x @ w_t.T + b`` (float32: x rows × in, ``w_t`` out × in), then ``max(·, 0)`` if ``relu``."""
    rows, n_in = x.shape
    n_out = w_t.shape[0]
    out = np.empty((rows, n_out), np.float32)
    for r in range(rows):
        for o in range(n_out):
            total = b[o]
            for i in range(n_in):
                total += x[r, i] * w_t[o, i]
            out[r, o] = max(total, np.float32(0.0)) if relu else total
    return out


class SARLNumpy:
    """``values(self_state (B, 5), humans (B, N, 7), mask (B, N)) -> (B,)`` from exported weights."""

    def __init__(self, arrays: dict[str, np.ndarray]):
        self.layers = {}
        for name in ("mlp1", "mlp2", "attention", "mlp3"):
            n = sum(1 for k in arrays if k.startswith(f"{name}.w"))
            if n == 0:
                raise ValueError(f"arrays: no weights for {name!r}")
            self.layers[name] = [  # weights transposed, (out, in): ``dense`` reads each output's row contiguously
                (np.ascontiguousarray(np.asarray(arrays[f"{name}.w{i}"], np.float32).T), np.ascontiguousarray(arrays[f"{name}.b{i}"], np.float32))
                for i in range(n)
            ]
        (w, bias), h = self.layers["attention"][0], self.layers["mlp1"][-1][1].shape[0]
        self.attention_split = (np.ascontiguousarray(w[:, :h]), np.ascontiguousarray(w[:, h:]), bias)
        joint_in, mlp3_in = self.layers["mlp1"][0][0].shape[1], self.layers["mlp3"][0][0].shape[1]
        self.self_dim = mlp3_in - self.layers["mlp2"][-1][1].shape[0]
        self.human_dim = joint_in - self.self_dim
        if self.self_dim < SELF_DIM or self.human_dim < HUMAN_DIM:
            raise ValueError(f"arrays: mlp1 takes {joint_in} inputs and mlp3 {mlp3_in}: not a robot state of >= {SELF_DIM} and a human's of >= {HUMAN_DIM}")

    @classmethod
    def load(cls, path) -> SARLNumpy:
        with np.load(path) as data:
            return cls({k: data[k] for k in data.files})

    def _mlp(self, name: str, x: np.ndarray, last_relu: bool, first: int = 0) -> np.ndarray:
        layers = self.layers[name]
        x = np.ascontiguousarray(x, np.float32)
        for i, (w, b) in enumerate(layers[first:], start=first):
            x = dense(x, w, b, i < len(layers) - 1 or last_relu)
        return x

    def values(self, self_state: np.ndarray, humans: np.ndarray, mask: np.ndarray) -> np.ndarray:
        self_state = np.asarray(self_state, np.float32)
        humans = np.asarray(humans, np.float32)
        mask = np.asarray(mask, np.float32)
        b, n, _ = humans.shape
        joint = np.concatenate([np.broadcast_to(self_state[:, None, :], (b, n, self_state.shape[1])), humans], axis=-1)
        embedding = self._mlp("mlp1", joint.reshape(b * n, -1), last_relu=True).reshape(b, n, -1)
        m = mask[..., None]
        context = (embedding * m).sum(1) / np.maximum(m.sum(1), 1.0)
        # the attention's first layer on [embedding, context], split: the context's half once per state, not per human
        w_embedding, w_context, bias = self.attention_split
        hidden = dense(embedding.reshape(b * n, -1), w_embedding, bias, False).reshape(b, n, -1)
        hidden += dense(np.ascontiguousarray(context), w_context, np.zeros_like(bias), False)[:, None, :]
        last = len(self.layers["attention"]) == 1
        hidden = hidden if last else np.maximum(hidden, np.float32(0.0))
        scores = (hidden.reshape(b * n, -1) if last else self._mlp("attention", hidden.reshape(b * n, -1), last_relu=False, first=1)).reshape(b, n)
        scores = np.where(mask > 0, scores, np.float32(MASK_FILL))
        scores = np.exp(scores - scores.max(axis=1, keepdims=True))
        weights = scores / scores.sum(axis=1, keepdims=True) * mask
        features = self._mlp("mlp2", embedding.reshape(b * n, -1), last_relu=False).reshape(b, n, -1)
        crowd = (weights[..., None] * features).sum(1)
        return self._mlp("mlp3", np.concatenate([self_state, crowd], axis=-1), last_relu=False)[:, 0]
