"""Run by ``test_wheel.py`` with the python of a scratch venv that holds the built wheel and nothing of
the checkout, from a temporary directory: ``python installed_checks.py CHECKOUT README``. An audit hook
records every file opened; any under the checkout fails the run (the README's quick start is handed in
as a path outside it), except under the dependencies' folders given after it (a venv inside the checkout,
as ``make`` makes ``.venv``). Prints one line per check and ``ok`` at the end."""

import os
import sys

CHECKOUT = os.path.realpath(sys.argv[1])
DEPENDENCIES = tuple(os.path.realpath(path) + os.sep for path in sys.argv[3:])
opened_in_checkout: list[str] = []


def _audit(event, args):
    if event == "open" and args and isinstance(args[0], (str, bytes, os.PathLike)):
        path = os.path.realpath(os.fsdecode(args[0]))
        if (path == CHECKOUT or path.startswith(CHECKOUT + os.sep)) and not path.startswith(DEPENDENCIES):
            opened_in_checkout.append(path)


sys.addaudithook(_audit)

import gymnasium as gym  # noqa: E402

import agents  # noqa: E402
import pathplan_env  # noqa: E402
from pathplan_env.maps.ros_maps import SHIPPED_MAPS, load_shipped_map  # noqa: E402
from pathplan_env.scenarios.presets import PRESETS  # noqa: E402

assert not os.path.realpath(pathplan_env.__file__).startswith(CHECKOUT), pathplan_env.__file__
assert os.path.realpath(pathplan_env.__file__).startswith(os.path.realpath(sys.prefix)), (pathplan_env.__file__, sys.prefix)
print("pathplan_env", pathplan_env.__version__, "from", os.path.dirname(pathplan_env.__file__))

# the README's quick start as written, on one episode of the harness instead of 20 (SB3's part needs the rl extra)
with open(sys.argv[2], encoding="utf-8") as readme:
    quick_start = readme.read().split("## Quick start", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
quick_start = quick_start.replace("episodes=20", "episodes=1, workers=1, plots=False")
if "stable_baselines3" not in sys.modules and __import__("importlib").util.find_spec("stable_baselines3") is None:
    quick_start = quick_start.split("# every agent works with SB3", 1)[0]
else:
    quick_start = quick_start.replace("n_eval_episodes=10", "n_eval_episodes=1")
exec(compile(quick_start, "README.md quick start", "exec"), {"__name__": "quick_start"})
print("quick start: ran")

for name in sorted(PRESETS):
    env = gym.make("DynamicObstacle-v0", scenario=name)
    env.reset(seed=0)
    env.close()
print(f"gym.make: {len(PRESETS)} presets")

for name in SHIPPED_MAPS:
    assert load_shipped_map(name).occupied.any(), name
print(f"maps: {', '.join(SHIPPED_MAPS)}")

#: the env each shipped model reads (the CrowdNav SARL models check for CrowdNav's humans, ppo-lidar for its sensor)
ENVS = {"sarl": {"scenario": "crowdnav-circle-crossing"}, "sarl-crossings": {"scenario": "crowdnav-square-crossing"}, "ppo-lidar": {"observation": "lidar"}}
learned = [name for name, preset in agents.presets().items() if preset.family in ("ppo", "sarl")]
for name in learned:
    agents.make(name, gym.make("DynamicObstacle-v0", **{"scenario": "random", **ENVS.get(name, {})}), seed=0)
print(f"models: {', '.join(learned)}")

assert not opened_in_checkout, opened_in_checkout[:5]
print("ok", flush=True)
# The exit status reports the checks above, not CPython's teardown: pymunk's Space finalizers can run after
# cffi's callbacks are gone and crash the exit (seen once in a few runs of this script, never before "ok")
os._exit(0)
