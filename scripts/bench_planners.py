"""Planner speed and quality, printed as ratios measured in one run.

1. Replan time: one plan of our compiled PSO (30 particles x 100 iterations, k = 2, 5 obstacles)
   and ABC (same number of objective evaluations), against pyswarms' GlobalBestPSO and mealpy's
   LDW_PSO and OriginalABC on the same objective and budget (``pip install -e .[bench]``; they are
   skipped when missing), and against a PSO written with one numpy call per iteration.
2. Quality: on static random scenes, the length each planner flies in the env divided by the exact
   shortest path (tangent graph, same inflation: robot radius + the planner's margin), for
   k = 1, 2, 3 waypoints.
3. Space-time planners: every replan's time over whole test episodes (random scenes, 8
   obstacles) at each Δd, median and p95, after a warm-up episode (compilation excluded).
   The unicycle's native planners (``robot="unicycle"``) run here too, on random scenes, and their
   ``-crowd`` variants on CrowdNav's circle crossing (its own speeds), with the median CPU time of a
   replan (this process's: what a shared machine's load changes least) beside the wall-clock times.
4. ``--dense`` (this part alone): the same at 30 and 50 obstacles x Δd 1, 2, 4 (issue 22's cells),
   on validation episodes (the seeds ``astar-spacetime``'s work budget was calibrated on), with each
   planner's success over them.
5. ``--unicycle`` (this part alone): part 3's unicycle rows (issue 23's target: replanning <= 5 ms median).
7. ``--static-clutter`` (this part alone): ``oracle-static``'s replan times among 300 resting
   cylinders (``clutter_scenario(n_cylinders=300)``: its first plan, which builds the tangent graph,
   and the replans after it, which fly on along it) and among 8 moving obstacles (random, Δd 0.5);
   then each space-time planner's replan median among the 300 resting cylinders beside its median
   among 8 moving obstacles (random, Δd 0.5, test episodes), and their ratio (issue 46's target: <= 2), with
   PSO's and ABC's objective evaluations a replan in both (where nothing has moved since the last replan they
   refine its best at a share of their budget: ``STILL_REFINE``).
6. ``--learned`` (this part alone): the shipped learned agents' acting time (one ``predict``, numpy
   forward, no torch) in the scenes each was trained for, over whole test episodes (issue 20's
   target: <= 2 ms median), wall clock and this process's CPU time.

    python scripts/bench_planners.py [--replans 200] [--scenes 20] [--spacetime-episodes 20]
    python scripts/bench_planners.py --dense [--dense-episodes 5] [--dense-obstacles 30,50] [--dense-delta-d 1,2,4]
    python scripts/bench_planners.py --unicycle [--spacetime-episodes 20] [--unicycle-planners pso-unicycle,pso-unicycle-crowd]
    python scripts/bench_planners.py --learned [--spacetime-episodes 20]
    python scripts/bench_planners.py --static-clutter [--spacetime-episodes 20] [--static-clutter-planners pso-spacetime,pso-spacetime?still_budget=0.3]
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np
from tqdm import tqdm

import agents
import pathplan_env  # noqa: F401  (registers the env)
from agents.planners.objective import evaluate
from pathplan_env.geometry.reference_path import shortest_path_to_goal

BUDGET_PARTICLES, BUDGET_ITERATIONS = 30, 100


def paper_case_3_scene(agent):
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-3", delta_d=0)
    obs, _ = env.reset(seed=0)
    return agent.scene(obs)


def median_ms(fn, repeats: int) -> float:
    fn()  # warm-up (numba cache load)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def numpy_pso(scene, lo, hi, rng, particles=BUDGET_PARTICLES, iterations=BUDGET_ITERATIONS):
    """Reference: the same adaptive PSO with one vectorised numpy update + objective call per iteration."""
    d = lo.size
    x = rng.uniform(lo, hi, size=(particles, d))
    v = np.zeros_like(x)
    cost = evaluate(x, scene)[0]
    pbest, pcost = x.copy(), cost.copy()
    g = pbest[np.argmin(pcost)]
    for it in range(iterations):
        w = 0.9 - 0.5 * it / iterations
        v = w * v + 1.49618 * rng.random(x.shape) * (pbest - x) + 1.49618 * rng.random(x.shape) * (g - x)
        x = np.clip(x + v, lo, hi)
        cost = evaluate(x, scene)[0]
        better = cost < pcost
        pbest[better], pcost[better] = x[better], cost[better]
        g = pbest[np.argmin(pcost)]
    return g


def replan_times(repeats: int) -> dict[str, float]:
    env = gym.make("DynamicObstacle-v0", scenario="paper-case-3", delta_d=0)
    pso = agents.make("pso", env, seed=0, population=BUDGET_PARTICLES, iterations=BUDGET_ITERATIONS)
    abc = agents.make("abc", env, seed=0, population=BUDGET_PARTICLES, iterations=BUDGET_ITERATIONS)
    scene = paper_case_3_scene(pso)
    lo, hi = pso.search_lo, pso.search_hi
    objective = lambda X: evaluate(X, scene)[0]
    rng = np.random.default_rng(0)
    times = {
        "ours: pso": median_ms(lambda: pso.optimize(scene, {}), repeats),
        "ours: abc": median_ms(lambda: abc.optimize(scene, {}), repeats),
        "numpy PSO (one call per iteration)": median_ms(lambda: numpy_pso(scene, lo, hi, rng), max(10, repeats // 10)),
    }
    try:
        import pyswarms

        def run_pyswarms():
            optimizer = pyswarms.single.GlobalBestPSO(
                n_particles=BUDGET_PARTICLES, dimensions=lo.size, options={"c1": 1.49618, "c2": 1.49618, "w": 0.7298}, bounds=(lo, hi)
            )
            optimizer.optimize(objective, iters=BUDGET_ITERATIONS, verbose=False)

        import logging

        logging.getLogger("pyswarms").setLevel(logging.ERROR)
        times["pyswarms GlobalBestPSO"] = median_ms(run_pyswarms, max(10, repeats // 10))
    except ImportError:
        print("pyswarms not installed (pip install -e .[bench]): skipped")
    try:
        from mealpy import ABC, PSO, FloatVar

        problem = {"obj_func": lambda x: float(objective(x[None])[0]), "bounds": FloatVar(lb=lo, ub=hi), "minmax": "min", "log_to": None}
        for label, model in (("mealpy LDW_PSO", lambda: PSO.LDW_PSO(epoch=BUDGET_ITERATIONS, pop_size=BUDGET_PARTICLES)),
                             ("mealpy OriginalABC", lambda: ABC.OriginalABC(epoch=BUDGET_ITERATIONS // 2, pop_size=BUDGET_PARTICLES))):  # fmt: skip
            times[label] = median_ms(lambda model=model: model().solve(problem, seed=0), 3)
    except ImportError:
        print("mealpy not installed (pip install -e .[bench]): skipped")
    return times


def optimality(n_scenes: int) -> list[tuple[str, int, float, float, float]]:
    rows = []
    configs = [(name, k) for name in ("pso", "abc", "pso-predictive", "abc-predictive") for k in (1, 2, 3)]
    for name, k in tqdm(configs, desc="optimality", leave=False):
        env = gym.make("DynamicObstacle-v0", scenario="random", delta_d=0)
        agent = agents.make(name, env, seed=0, n_waypoints=k)
        ratios, successes = [], 0
        for seed in range(n_scenes):
            info = agents.rollout(agent, env, seed=10_000 + seed)
            # the harness's reference, with the planner's own margin (what it can be optimal for)
            optimum = shortest_path_to_goal(env.unwrapped.scenario, margin=agent.margin)
            if info["is_success"] and np.isfinite(optimum):
                successes += 1
                ratios.append(info["path_length"] / optimum)
        rows.append((name, k, successes / n_scenes, float(np.median(ratios)), float(np.percentile(ratios, 90))))
    return rows


HOLONOMIC_SPACETIME = ("astar-spacetime", "pso-spacetime", "abc-spacetime")
UNICYCLE_SPACETIME = ("astar-unicycle", "pso-unicycle", "abc-unicycle")
SPACETIME_PLANNERS = HOLONOMIC_SPACETIME + UNICYCLE_SPACETIME
#: the unicycle's planners for crowds that steer, timed on CrowdNav's circle crossing (its own speeds)
CROWD_SCENARIO, CROWD_PLANNERS = "crowdnav-circle-crossing", ("astar-unicycle-crowd", "pso-unicycle-crowd", "abc-unicycle-crowd")
SPACETIME_TARGET_MS = (5.0, 50.0)  # median, p95


def replan_cell(name: str, delta_d: float | None, seeds, n_obstacles: int | None = None, scenario: str = "random",
                cpu: list | None = None, evaluations: list | None = None) -> tuple[list[float], int]:  # fmt: skip
    """Every replan's time (ms) of ``name`` over the episodes of ``seeds`` (``scenario``: random scenes
    by default), after a warm-up episode, and how many of them it won; ``cpu``, if given, receives each
    replan's CPU time (ms, this process's), ``evaluations`` a PSO's or ABC's objective evaluations in it."""
    from pathplan_env.scenarios.splits import heldout_seeds

    base, settings = agents.registry.split_settings(name)  # a name may carry settings: "pso-spacetime?still_budget=0.3"
    robot = "unicycle" if base in agents.UNICYCLE_AGENTS else "holonomic"
    env = gym.make("DynamicObstacle-v0", scenario=scenario, delta_d=delta_d, robot=robot, n_obstacles=n_obstacles,
                   observation=agents.observation_of(base))
    agent = agents.make(base, env, seed=0, **settings)
    agents.rollout(agent, env, seed=heldout_seeds(9, 1)[0])  # warm-up: numba's cache loads here
    times, wins = [], 0
    for seed in seeds:
        agent.reset()
        obs, _ = env.reset(seed=seed)
        while True:
            begin = time.process_time()
            action, _ = agent.predict(obs, deterministic=True)
            if cpu is not None:
                cpu.append(1e3 * (time.process_time() - begin))
            if evaluations is not None and hasattr(agent, "last_evaluations"):
                evaluations.append(agent.last_evaluations)
            times.append(1e3 * agent.last_plan_seconds)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        wins += bool(info["is_success"])
    return times, wins


def spacetime_replan_times(episodes: int, deltas=(0.25, 0.5, 1.0, 2.0), planners=SPACETIME_PLANNERS,
                           crowd_planners=CROWD_PLANNERS) -> list[tuple[str, str, float, float, float, int]]:  # fmt: skip
    """``(planner, scene, median ms, p95 ms, median CPU ms, replans)`` over every replan of ``episodes``
    test episodes: random scenes at each Δd, then the crowd planners on CrowdNav's circle crossing."""
    from pathplan_env.scenarios.splits import heldout_seeds

    cells = [(name, delta_d, "random") for name in planners for delta_d in deltas]
    cells += [(name, None, CROWD_SCENARIO) for name in crowd_planners]
    rows = []
    for name, delta_d, scenario in tqdm(cells, desc="space-time replans", leave=False):
        cpu: list[float] = []
        times, _ = replan_cell(name, delta_d, heldout_seeds(0, episodes), scenario=scenario, cpu=cpu)
        scene = f"Δd {delta_d:g}" if scenario == "random" else scenario
        rows.append((name, scene, float(np.median(times)), float(np.percentile(times, 95)), float(np.median(cpu)), len(times)))
    return rows


def print_spacetime(episodes: int, planners=SPACETIME_PLANNERS, crowd_planners=CROWD_PLANNERS) -> None:
    median_target, p95_target = SPACETIME_TARGET_MS
    print(f"\nSpace-time planners: every replan of {episodes} test episodes (random, 8 obstacles; {CROWD_SCENARIO} at its own speeds), ms")
    print(f"| planner | scene | replans | median (target <= {median_target:g}) | p95 (target <= {p95_target:g}) | median CPU |")
    print("|---|---|---:|---:|---:|---:|")
    for name, scene, median, p95, cpu, count in spacetime_replan_times(episodes, planners=planners, crowd_planners=crowd_planners):
        print(f"| {name} | {scene} | {count} | {median:.2f} | {p95:.2f} | {cpu:.2f} |", flush=True)


#: The shipped learned agents and the scenes each was trained for: ``(agent, scenario, Δd values; None: the scenario's own)``.
LEARNED_CELLS = (
    ("ppo", "random", (0.25, 0.5, 1.0)), ("ppo-set", "random", (0.25, 0.5, 1.0)), ("sarl-random", "random", (0.25, 0.5, 1.0)),
    ("sarl", "crowdnav-circle-crossing", (None,)), ("sarl-crossings", "crowdnav-circle-crossing", (None,)),
    ("sarl-crossings", "crowdnav-square-crossing", (None,)),
)  # fmt: skip
ACTING_TARGET_MS = 2.0  # median, issue 20


def print_learned(episodes: int) -> None:
    from pathplan_env.scenarios.splits import heldout_seeds

    print(f"\nLearned agents: every action of {episodes} test episodes, ms (numpy forward; target <= {ACTING_TARGET_MS:g} median)")
    print("| agent | scene | actions | median | p95 | median CPU | success |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for name, scenario, deltas in LEARNED_CELLS:
        for delta_d in deltas:
            cpu: list[float] = []
            times, wins = replan_cell(name, delta_d, heldout_seeds(0, episodes), scenario=scenario, cpu=cpu)
            scene = scenario + (f", Δd {delta_d:g}" if delta_d is not None else "")
            print(f"| {name} | {scene} | {len(times)} | {np.median(times):.2f} | {np.percentile(times, 95):.2f} | {np.median(cpu):.2f} "
                  f"| {wins}/{episodes} |", flush=True)  # fmt: skip


DENSE_PLANNERS = ("astar-spacetime", "pso-spacetime", "abc-spacetime")


def dense_replan_times(episodes: int, counts=(30, 50), deltas=(1.0, 2.0, 4.0), planners=DENSE_PLANNERS) -> list[tuple]:
    """``(planner, obstacles, Δd, median ms, p95 ms, replans, wins)`` over ``episodes`` validation episodes a cell."""
    from pathplan_env.scenarios.splits import episode_seeds

    rows = []
    cells = [(name, n, d) for n in counts for d in deltas for name in planners]
    for name, n, delta_d in tqdm(cells, desc="dense replans", leave=False):
        times, wins = replan_cell(name, delta_d, episode_seeds("validation", 0, episodes), n)
        rows.append((name, n, delta_d, float(np.median(times)), float(np.percentile(times, 95)), len(times), wins))
    return rows


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--replans", type=int, default=200)
    parser.add_argument("--scenes", type=int, default=20)
    parser.add_argument("--spacetime-episodes", type=int, default=20)
    parser.add_argument("--dense", action="store_true", help="only the dense cells (30 and 50 obstacles x Δd 1, 2, 4)")
    parser.add_argument("--static-clutter", action="store_true",
                        help="only the replan times among 300 resting cylinders: oracle-static's, the space-time planners' beside 8 obstacles")
    parser.add_argument("--static-clutter-planners", default=",".join(HOLONOMIC_SPACETIME),
                        help="comma-separated space-time planners of --static-clutter, each may carry settings after '?' "
                             "(pso-spacetime?still_budget=0.3&still_spread=0.3)")
    parser.add_argument("--learned", action="store_true", help="only the learned agents' acting times (their own scenes)")
    parser.add_argument("--unicycle", action="store_true", help="only the unicycle's space-time rows (random scenes, circle crossing)")
    parser.add_argument("--unicycle-planners", default=",".join(UNICYCLE_SPACETIME + CROWD_PLANNERS),
                        help="comma-separated: which of them (the -crowd ones on the circle crossing)")
    parser.add_argument("--dense-episodes", type=int, default=5, help="validation episodes a dense cell")
    parser.add_argument("--dense-obstacles", default="30,50", help="comma-separated obstacle counts of the dense cells")
    parser.add_argument("--dense-delta-d", default="1,2,4", help="comma-separated Δd of the dense cells")
    parser.add_argument("--dense-planners", default=",".join(DENSE_PLANNERS), help="comma-separated space-time planners")
    return parser


def parse_args(argv=None) -> argparse.Namespace:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        args.dense_obstacles = [int(v) for v in args.dense_obstacles.split(",")]
        args.dense_delta_d = [float(v) for v in args.dense_delta_d.split(",")]
    except ValueError as error:
        parser.error(f"--dense-obstacles / --dense-delta-d: comma-separated numbers ({error})")
    args.dense_planners = [p.strip() for p in args.dense_planners.split(",") if p.strip()]
    args.unicycle_planners = [p.strip() for p in args.unicycle_planners.split(",") if p.strip()]
    args.static_clutter_planners = [p.strip() for p in args.static_clutter_planners.split(",") if p.strip()]
    try:
        clutter_bases = {agents.registry.split_settings(p)[0] for p in args.static_clutter_planners}
    except ValueError as error:
        parser.error(f"--static-clutter-planners: {error}")
    if clutter_bases - set(HOLONOMIC_SPACETIME):
        parser.error(f"--static-clutter-planners: each one of {HOLONOMIC_SPACETIME}, with settings or without")
    if set(args.unicycle_planners) - set(UNICYCLE_SPACETIME + CROWD_PLANNERS):
        parser.error(f"--unicycle-planners: each one of {UNICYCLE_SPACETIME + CROWD_PLANNERS}")
    unknown = sorted(set(args.dense_planners) - set(agents.available()))
    if unknown or args.dense_episodes < 1:
        parser.error(f"--dense-planners: unknown {unknown}" if unknown else "--dense-episodes must be >= 1")
    return args


def print_dense(args: argparse.Namespace) -> None:
    median_target, p95_target = SPACETIME_TARGET_MS
    print(f"\nSpace-time planners, dense: every replan of {args.dense_episodes} validation episodes a cell (random), ms")
    print(f"| planner | obstacles | Δd | replans | median (target <= {median_target:g}) | p95 (target <= {p95_target:g}) | success |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    rows = dense_replan_times(args.dense_episodes, args.dense_obstacles, args.dense_delta_d, args.dense_planners)
    for name, n, delta_d, median, p95, count, wins in rows:
        print(f"| {name} | {n} | {delta_d:g} | {count} | {median:.2f} | {p95:.2f} | {wins}/{args.dense_episodes} |")


def static_clutter_times(episodes: int) -> list[tuple[str, int, float, float, float, float]]:
    """``oracle-static``'s plan times (ms) over whole episodes: (scene, plans, first plan's median, later
    replans' median, and the same two in this process's CPU time)."""
    from pathplan_env.scenarios.clutter import clutter_scenario

    rows = []
    scenes = (("300 resting cylinders", lambda seed: clutter_scenario(np.random.default_rng(seed), n_cylinders=300)),
              ("random, 8 moving (Δd 0.5)", None))  # fmt: skip
    for label, make in scenes:
        env = gym.make("DynamicObstacle-v0", scenario=make(0) if make else "random", delta_d=None if make else 0.5)
        agent = agents.make("oracle-static", env, seed=0)
        agents.rollout(agent, env, seed=0)  # warm-up: compilation
        first, later, first_cpu, later_cpu = [], [], [], []
        for seed in range(1, episodes + 1):
            if make:
                env = gym.make("DynamicObstacle-v0", scenario=make(seed))
                agent = agents.make("oracle-static", env, seed=0)
            agent.reset()
            obs, _ = env.reset(seed=seed)
            for step in range(400):
                begin = time.process_time()
                action, _ = agent.predict(obs, deterministic=True)
                (first_cpu if step == 0 else later_cpu).append(1e3 * (time.process_time() - begin))
                (first if step == 0 else later).append(1e3 * agent.last_plan_seconds)
                obs, _, terminated, truncated, _ = env.step(action)
                if terminated or truncated:
                    break
        rows.append((label, len(first) + len(later), float(np.median(first)), float(np.median(later)), float(np.median(first_cpu)),
                     float(np.median(later_cpu))))  # fmt: skip
    return rows


def clutter_replans(name: str, episodes: int, n_cylinders: int = 300, evaluations: list | None = None) -> tuple[list[float], list[float], int]:
    """Every replan's wall-clock and CPU time (ms) of ``name`` over ``episodes`` clutter episodes of
    ``n_cylinders`` resting cylinders and nothing moving (seeds 1, 2, ...), after a warm-up episode; and its wins.
    ``evaluations``, if given, receives a PSO's or ABC's objective evaluations in each replan."""
    from pathplan_env.scenarios.clutter import clutter_scenario

    times, cpu, wins = [], [], 0
    for seed in range(episodes + 1):
        env = gym.make("DynamicObstacle-v0", scenario=clutter_scenario(np.random.default_rng(seed), n_cylinders=n_cylinders))
        base, settings = agents.registry.split_settings(name)
        agent = agents.make(base, env, seed=0, **settings)
        obs, _ = env.reset(seed=seed)
        while True:
            begin = time.process_time()
            action, _ = agent.predict(obs, deterministic=True)
            if seed > 0:  # seed 0: the warm-up (numba's cache loads there)
                cpu.append(1e3 * (time.process_time() - begin))
                times.append(1e3 * agent.last_plan_seconds)
                if evaluations is not None and hasattr(agent, "last_evaluations"):
                    evaluations.append(agent.last_evaluations)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        wins += seed > 0 and bool(info["is_success"])
    return times, cpu, wins


def print_static_clutter(episodes: int, planners=HOLONOMIC_SPACETIME) -> None:
    print(f"\noracle-static: plan times over {episodes} episodes, ms (the first builds the graph; among resting shapes the rest fly on along it)")
    print("| scene | plans | first plan (median) | later replans (median) | first plan, CPU | later replans, CPU |")
    print("|---|---:|---:|---:|---:|---:|")
    for label, count, first, later, first_cpu, later_cpu in static_clutter_times(episodes):
        print(f"| {label} | {count} | {first:.1f} | {later:.2f} | {first_cpu:.1f} | {later_cpu:.2f} |", flush=True)
    from pathplan_env.scenarios.splits import heldout_seeds

    print(f"\nSpace-time planners: every replan of {episodes} episodes among 300 resting cylinders (nothing moving) beside "
          f"every replan of {episodes} test episodes among 8 moving obstacles (random, Δd 0.5), ms (target: ratio <= 2)")
    print("| planner | replans, 300 cylinders | median | median CPU | success | replans, 8 obstacles | median | median CPU | ratio (median CPU) "
          "| objective evaluations a replan, median: 300 cylinders / 8 obstacles |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in planners:
        many_evaluations: list[int] = []
        few_evaluations: list[int] = []
        times, cpu, wins = clutter_replans(name, episodes, evaluations=many_evaluations)
        few_cpu: list[float] = []
        few, _ = replan_cell(name, 0.5, heldout_seeds(0, episodes), cpu=few_cpu, evaluations=few_evaluations)
        ratio = np.median(cpu) / np.median(few_cpu)  # CPU: what a shared machine's load changes least
        spent = f"{np.median(many_evaluations):.0f} / {np.median(few_evaluations):.0f}" if many_evaluations else "-"  # (the A* counts work otherwise)
        print(f"| {name} | {len(times)} | {np.median(times):.2f} | {np.median(cpu):.2f} | {wins}/{episodes} | {len(few)} | {np.median(few):.2f} "
              f"| {np.median(few_cpu):.2f} | {ratio:.1f} | {spent} |", flush=True)  # fmt: skip


def main(argv=None) -> None:
    args = parse_args(argv)
    if args.static_clutter:
        print_static_clutter(args.spacetime_episodes, args.static_clutter_planners)
        return
    if args.dense:
        print_dense(args)
        return
    if args.learned:
        print_learned(args.spacetime_episodes)
        return
    if args.unicycle:
        chosen = args.unicycle_planners
        print_spacetime(args.spacetime_episodes, [p for p in UNICYCLE_SPACETIME if p in chosen], [p for p in CROWD_PLANNERS if p in chosen])
        return

    times = replan_times(args.replans)
    ours = times["ours: pso"]
    print(f"\nReplan time, paper-case-3 (5 obstacles), k = 2, {BUDGET_PARTICLES} x {BUDGET_ITERATIONS} evaluations; median")
    print("| planner | ms per replan | ours: pso is faster by |")
    print("|---|---:|---:|")
    for label, ms in times.items():
        print(f"| {label} | {ms:.3f} | {ms / ours:.1f}x |")

    print(f"\nFlown path / exact shortest path on {args.scenes} static random scenes (8 obstacles)")
    print("| planner | k | success | median ratio | p90 ratio |")
    print("|---|---:|---:|---:|---:|")
    for name, k, success, median, p90 in optimality(args.scenes):
        print(f"| {name} | {k} | {success:.2f} | {median:.4f} | {p90:.4f} |")

    print_spacetime(args.spacetime_episodes)


if __name__ == "__main__":
    main()
