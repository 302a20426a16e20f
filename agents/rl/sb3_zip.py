"""What a stable-baselines3 model zip holds, read without unpickling anything: its entries and sizes
from the zip's directory (bounded before anything is decompressed), its ``data`` JSON, and the
algorithms that could have saved it (rl-zoo3's names)."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

#: the policy class's module in a saved model -> the algorithms that save it
_POLICY_MODULES = {
    "stable_baselines3.sac.policies": ("sac",),
    "stable_baselines3.td3.policies": ("td3", "ddpg"),
    "stable_baselines3.dqn.policies": ("dqn",),
    "sb3_contrib.ars.policies": ("ars",),
    "sb3_contrib.crossq.policies": ("crossq",),
    "sb3_contrib.qrdqn.policies": ("qrdqn",),
    "sb3_contrib.tqc.policies": ("tqc",),
}
_STATEFUL = ("sb3_contrib.common.recurrent", "sb3_contrib.common.maskable")  # need LSTM states or action masks

#: The largest ``data`` JSON read from a zip (SB3 writes a few kB; a bomb expands to gigabytes).
MAX_DATA_BYTES = 16 * 2**20
#: The largest a zip may expand to in all (SB3's policies of this task are a few MB).
MAX_MODEL_BYTES = 1 * 2**30
#: What SB3's ``save`` always writes: the JSON of the algorithm and the policy's weights.
REQUIRED_ENTRIES = ("data", "policy.pth")


def saved_data(path: Path) -> dict:
    """The ``data`` JSON of an SB3 zip (read as JSON: nothing is unpickled), after checking from the
    zip's directory, before anything is decompressed, that it holds SB3's entries and expands to a
    bounded size."""
    def refuse(reason: str) -> ValueError:
        return ValueError(f"path: {path} is not a stable-baselines3 model (a zip holding {' and '.join(REQUIRED_ENTRIES)}): {reason}")

    try:
        with zipfile.ZipFile(path) as archive:
            entries = {info.filename: info for info in archive.infolist()}
            missing = [name for name in REQUIRED_ENTRIES if name not in entries]
            if missing:
                raise refuse(f"no {' or '.join(missing)} in it")
            if entries["data"].file_size > MAX_DATA_BYTES:
                raise refuse(f"its 'data' expands to {entries['data'].file_size} bytes, over {MAX_DATA_BYTES}")
            expanded = sum(info.file_size for info in entries.values())
            if expanded > MAX_MODEL_BYTES:
                raise refuse(f"it expands to {expanded} bytes, over {MAX_MODEL_BYTES}")
            with archive.open("data") as entry:  # read at most the stated size: a lying header cannot make it more
                text = entry.read(MAX_DATA_BYTES + 1)
            data = json.loads(text)
    except (zipfile.BadZipFile, json.JSONDecodeError, UnicodeDecodeError, OSError, EOFError) as error:
        raise refuse(str(error)) from None
    if not isinstance(data, dict):
        raise refuse(f"its 'data' is a JSON {type(data).__name__}, not an object")
    return data


def detect_algorithm(path: str | Path) -> tuple[str, ...]:
    """The algorithms (rl-zoo3's names) that could have saved the model at ``path``, the likeliest
    first; empty if the zip does not tell (a policy class from the user's own module).

    Read from the ``data`` JSON: the policy class's module, then the algorithm's hyperparameters
    for the algorithms sharing a policy (PPO's ``clip_range``, TRPO's ``cg_max_steps``; DDPG is TD3
    with ``policy_delay=1`` and ``target_noise_clip=0``)."""
    data = saved_data(Path(path))
    policy_class = data.get("policy_class")
    module = str(policy_class.get("__module__", "")) if isinstance(policy_class, dict) else ""
    if module.startswith(_STATEFUL):
        raise ValueError(f"path: {path} holds a recurrent or maskable sb3-contrib policy ({module}), which this agent does not run")
    if module == "stable_baselines3.common.policies":  # ActorCriticPolicy: PPO, A2C or TRPO
        return ("ppo",) if "clip_range" in data else ("trpo",) if "cg_max_steps" in data else ("a2c",)
    candidates = _POLICY_MODULES.get(module, ())
    if candidates == ("td3", "ddpg") and data.get("policy_delay") == 1 and data.get("target_noise_clip") == 0.0:
        candidates = ("ddpg", "td3")
    return candidates


__all__ = ["MAX_DATA_BYTES", "MAX_MODEL_BYTES", "REQUIRED_ENTRIES", "detect_algorithm", "saved_data"]
