"""scripts/bench_crowds.py --env-split: the parts it times are the env's own, on the env's plain (fused) step."""

import importlib
import importlib.util
import math
import sys
from pathlib import Path

import pytest

from pathplan_env.world.navground_peer import crowd_scene

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
bench_crowds = importlib.import_module("bench_crowds")

PARTS = ("env step", "World.step", "action's move", "observation", "reward terms", "info", "floor: World.step + the API's dicts",
         "fused compiled call", "floor: fused call + the API's dicts")  # fmt: skip


def test_the_split_times_every_part():
    parts = bench_crowds.env_split(crowd_scene("circle", 2), steps=3, envs=2)
    assert tuple(parts) == PARTS
    assert all(math.isfinite(us) and us > 0.0 for us in parts.values())


@pytest.mark.skipif(importlib.util.find_spec("navground") is None, reason="navground (the crowds-bench extra) is not installed")
def test_the_split_times_navgrounds_step_alike():
    parts = bench_crowds.env_split(crowd_scene("circle", 2), steps=3, envs=2, with_peer=True)
    assert tuple(parts) == (*PARTS, "navground's step")
    assert parts["navground's step"] > 0.0
