"""SARL's value network (:mod:`agents.rl.sarl.net`) evaluated without torch: the agent acts on a core install.

The forward pass is a few small matrix products over (actions × humans) rows. Each dense layer is a
compiled single-threaded loop (:func:`dense`), not numpy's ``@``: OpenBLAS splits even these small
products over threads, which on a busy 2-core machine took 20-70 ms a forward instead of about 1.
Activations are feature-major (features × rows): the inner loop runs along the rows, contiguous,
four outputs at a time, which vectorises without reductions where a dot product per output did not
(``scripts/bench_planners.py --learned`` times the agents that use it).
"""

from __future__ import annotations

import numba
import numpy as np

#: The robot's own features (:func:`agents.rl.sarl.lookahead.joint_state`) and each human's, CrowdNav's
#: (a setting with more features, ``SARLFeatures``, has wider inputs: the weights say which).
SELF_DIM, HUMAN_DIM = 5, 7
#: Hidden sizes: CrowdNav's sarl has mlp1 150-100, mlp2 100-50, attention 100-100, mlp3 150-100-100;
#: these are about a quarter of its multiply-adds, so that 81 moves score within a millisecond.
HIDDEN = {"mlp1": (100, 50), "mlp2": (50,), "attention": (50,), "mlp3": (100, 50)}
#: Rows (states × humans) a forward takes at once: a larger batch (a standing search's grid: 11,664 states × 5 humans)
#: goes in pieces whose activations stay in the core's cache (that grid's build took about twice as long in one piece);
#: the two-step lookahead's 243 states × 8 obstacles stay one piece.
CHUNK_ROWS = 2048
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
def dense(x_t, w_t, b, relu):
    """``w_t @ x_t + b`` feature-major (float32: ``x_t`` in × rows, ``w_t`` out × in; out × rows), then ``max(·, 0)`` if ``relu``."""
    n_in, rows = x_t.shape
    n_out = w_t.shape[0]
    out = np.empty((n_out, rows), np.float32)
    for o in range(n_out):
        out[o, :] = b[o]
    o = 0
    while o + 4 <= n_out:  # four outputs share each input row's load
        a0, a1, a2, a3 = out[o], out[o + 1], out[o + 2], out[o + 3]
        for i in range(n_in):
            w0, w1, w2, w3 = w_t[o, i], w_t[o + 1, i], w_t[o + 2, i], w_t[o + 3, i]
            x = x_t[i]
            for r in range(rows):
                v = x[r]
                a0[r] += w0 * v
                a1[r] += w1 * v
                a2[r] += w2 * v
                a3[r] += w3 * v
        o += 4
    for k in range(o, n_out):
        acc = out[k]
        for i in range(n_in):
            w, x = w_t[k, i], x_t[i]
            for r in range(rows):
                acc[r] += w * x[r]
    if relu:
        for k in range(n_out):
            for r in range(rows):
                out[k, r] = max(out[k, r], np.float32(0.0))
    return out


@numba.njit(cache=True, fastmath=True)
def masked_mean(x, mask):
    """``x`` (F, B, N) averaged over the present humans of each state (``mask`` (B, N) > 0): (F, B); 0 without any."""
    f_dim, b_dim, n_dim = x.shape
    out = np.zeros((f_dim, b_dim), np.float32)
    for b in range(b_dim):
        count = np.float32(0.0)
        for n in range(n_dim):
            count += mask[b, n]
        scale = np.float32(1.0) / max(count, np.float32(1.0))
        for f in range(f_dim):
            total = np.float32(0.0)
            for n in range(n_dim):
                total += x[f, b, n] * mask[b, n]
            out[f, b] = total * scale
    return out


@numba.njit(cache=True)
def attention_pool(scores, mask, features):
    """The softmax of ``scores`` (B, N) over each state's present humans, weighting ``features`` (F, B, N): (F, B)."""
    f_dim, b_dim, n_dim = features.shape
    out = np.zeros((f_dim, b_dim), np.float32)
    weights = np.empty(n_dim, np.float32)
    for b in range(b_dim):
        top = np.float32(MASK_FILL)
        for n in range(n_dim):
            if mask[b, n] > 0:
                top = max(top, scores[b, n])
        total = np.float32(0.0)
        for n in range(n_dim):
            weights[n] = np.exp((scores[b, n] if mask[b, n] > 0 else np.float32(MASK_FILL)) - top)
            total += weights[n]
        for n in range(n_dim):
            weights[n] = weights[n] / total * mask[b, n]
        for f in range(f_dim):
            acc = np.float32(0.0)
            for n in range(n_dim):
                acc += weights[n] * features[f, b, n]
            out[f, b] = acc
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

    def _mlp(self, name: str, x_t: np.ndarray, last_relu: bool, first: int = 0) -> np.ndarray:
        """The MLP ``name`` (from its layer ``first``) on feature-major ``x_t`` (in × rows)."""
        layers = self.layers[name]
        for i, (w, b) in enumerate(layers[first:], start=first):
            x_t = dense(x_t, w, b, i < len(layers) - 1 or last_relu)
        return x_t

    def values(self, self_state: np.ndarray, humans: np.ndarray, mask: np.ndarray) -> np.ndarray:
        b, n = np.shape(mask)
        step = max(1, CHUNK_ROWS // max(n, 1))
        if b <= step:
            return self._values(self_state, humans, mask)
        return np.concatenate([self._values(self_state[i : i + step], humans[i : i + step], mask[i : i + step]) for i in range(0, b, step)])

    def _values(self, self_state: np.ndarray, humans: np.ndarray, mask: np.ndarray) -> np.ndarray:
        self_state = np.asarray(self_state, np.float32)
        humans = np.asarray(humans, np.float32)
        mask = np.ascontiguousarray(mask, np.float32)
        b, n, _ = humans.shape
        s = self_state.shape[1]
        joint_t = np.empty((s + humans.shape[2], b, n), np.float32)  # feature-major: every layer's rows are (state, human) pairs
        joint_t[:s] = self_state.T[:, :, None]
        joint_t[s:] = humans.transpose(2, 0, 1)
        embedding = self._mlp("mlp1", joint_t.reshape(len(joint_t), b * n), last_relu=True)  # (E, b·n)
        e = len(embedding)
        embedding3 = embedding.reshape(e, b, n)
        context = masked_mean(embedding3, mask)  # (E, b)
        # the attention's first layer on [embedding, context], split: the context's half once per state, not per human
        w_embedding, w_context, bias = self.attention_split
        hidden = dense(embedding, w_embedding, bias, False).reshape(len(bias), b, n)
        hidden += dense(np.ascontiguousarray(context), w_context, np.zeros_like(bias), False)[:, :, None]
        last = len(self.layers["attention"]) == 1
        hidden = hidden if last else np.maximum(hidden, np.float32(0.0))
        scores = (hidden if last else self._mlp("attention", hidden.reshape(len(hidden), b * n), last_relu=False, first=1)).reshape(b, n)
        features = self._mlp("mlp2", embedding, last_relu=False)
        crowd = attention_pool(np.ascontiguousarray(scores), mask, features.reshape(len(features), b, n))  # (F, b)
        return self._mlp("mlp3", np.concatenate([self_state.T, crowd]), last_relu=False)[0]
