"""Time the harness's reference path (the length-ratio metric's exact static shortest path) before and
after 0.2.0: the numpy tangent graph (``geometry.shortest_paths.shortest_path``) against the compiled
one (``geometry.tangent_graph``) that ``shortest_path_to_goal`` now uses, and its second call on the
same scene (cached). Scenes: the ``clutter`` preset's first scene (200 resting cylinders of radius 0.075 m), and the
shipped office map (a ROS map_server YAML) with 5 bouncing discs.

    python scripts/bench_reference_path.py
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pathplan_env import Obstacle, Scenario
from pathplan_env.geometry import reference_path
from pathplan_env.maps.ros_maps import load_shipped_map
from pathplan_env.scenarios.on_maps import scenario_kwargs
from pathplan_env.scenarios.presets import make_scenario


def _cylinders() -> Scenario:
    return make_scenario("clutter", np.random.default_rng(0))  # 200 resting cylinders, a corridor through them


def _office() -> Scenario:
    kwargs = scenario_kwargs(load_shipped_map("office"), np.random.default_rng(0), n_obstacles=5, obstacle_radius=0.3, obstacle_speed=0.75)
    return Scenario(**kwargs, name="office")


def _timed(fn, *args):
    begin = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - begin


def build_parser() -> argparse.ArgumentParser:
    return argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)


def parse_args(argv=None) -> argparse.Namespace:
    return build_parser().parse_args(argv)


def main(argv=None) -> None:
    parse_args(argv)
    reference_path.shortest_path_to_goal(Scenario(bounds=(0, 0, 5, 5), start=(1, 1), goal=(4, 4), obstacles=(Obstacle((2.5, 2.5), 0.5),)))  # compile
    print("| scene | discs | capsules | length m | numpy graph s | compiled s | cached s | lengths equal (1e-9) |")
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for scenario in (_cylinders(), _office()):
        before, t_before = _timed(reference_path.numpy_path_to_goal, scenario)
        after, t_after = _timed(reference_path.shortest_path_to_goal, scenario)
        again, t_again = _timed(reference_path.shortest_path_to_goal, scenario)
        equal = (before == after or abs(before - after) <= 1e-9) and after == again
        print(f"| {scenario.name} | {scenario.n_obstacles} | {len(scenario.static_segments)} | {after:.3f} | {t_before:.2f} | {t_after:.3f} | "
              f"{t_again * 1e3:.3f} ms | {equal} |", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
