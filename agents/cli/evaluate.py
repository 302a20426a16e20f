"""Benchmark agents x scenarios x Δd on a fixed test split, in parallel, with honest statistics.

    pathplan-env evaluate --agents pso,abc,pso-spacetime --scenarios paper-case-1,random \
        --delta-d 0,0.125,0.25,0.5,1 --episodes 100 --seed 0 --out results/NAME
    pathplan-env evaluate --suite default        # the README's main job (~3 minutes on 2 cores)
    pathplan-env evaluate --agents pf_agent:PotentialField,pso --scenarios scenes/corridor.yaml --episodes 50
    pathplan-env evaluate --agents orca --scenarios crowdnav-circle-crossing --delta-d 0.8333333333333334 \
        --episodes 500 --split crowdnav --out results/crowdnav_cases   # CrowdNav's own 500 test cases

Every (agent, scenario, Δd) cell runs the same episodes, and the privileged oracle-clairvoyant runs
on them too: each cell reports its physical limit and every agent its success ÷ limit. Writes
``episodes.jsonl`` as episodes finish (``--resume`` continues a run), then ``summary.json``,
``episodes.csv``, ``table.md`` (every cell's row), ``report.html`` and plots to ``--out``, and prints
the summary tables (success ÷ limit against Δd per scenario). The work is done by
``agents.evaluation``, which a Python user can call directly.

Your own agent: ``module:attribute`` (a module on the path or in the current directory) or
``path/to/file.py:attribute``, naming a class, a factory or an object with SB3's ``predict``; a learned
agent's checkpoint as ``ppo@runs/a/best_model.zip``; a registered agent with parameters over its own as
``'pso?iterations=20&population=8'`` (values Python literals). Your own scene: a JSON or YAML file of a
``pathplan_env.Scenario``. Any entry takes a label as ``label=entry``; a label given twice is an error.

Env options reach every episode's env (``gym.make`` keywords): ``--observation NAME`` with
``--observation-params JSON``, or any keyword through ``--env-options JSON``; a bad one stops the run
before any episode, with the env's own message.

``python scripts/evaluate.py`` is the same command, with the same flags.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

from agents.evaluation import LIMIT_AGENT, SUITES, EvaluationSettings, evaluate
from agents.evaluation.harness import TABLE_NAME
from agents.evaluation.records import OWN_SPEEDS
from agents.evaluation.reporting import social_table, summary_tables
from pathplan_env.scenarios.splits import SPLITS

#: gym.make keywords with a flag of their own: ``--NAME`` (a registered type's name) and ``--NAME-params``
#: (its parameters as JSON), into the env options ``NAME`` and ``NAME_params``. (``robot`` joins the same way.)
ENV_OPTION_FLAGS = {
    "observation": "the observation type (pathplan_env.sensors.observations)",
    "robot": "the robot model (holonomic, unicycle; pathplan_env.robots.actions.ROBOTS)",
}


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--suite", choices=sorted(SUITES), help="a preset configuration (explicit flags override it)")
    parser.add_argument("--agents", help="comma-separated: registered names (agents.available()), name@model_path, "
                        "module:attribute, path/to/file.py:attribute, each optionally label=entry (no commas in paths)")
    parser.add_argument("--scenarios", help="comma-separated: presets or .json/.yaml/.yml scenario files, each optionally "
                        "label=entry (no commas in paths)")
    parser.add_argument("--delta-d", help="comma-separated Δd values; 'own' runs a scenario at its own obstacle speeds "
                        "(the default when every scenario is a file)")
    parser.add_argument("--episodes", type=int, help="episodes per cell")
    parser.add_argument("--seed", type=int, default=0, help="split seed")
    parser.add_argument("--split", choices=SPLITS, default="test",
                        help="test episodes (reports), validation episodes (model selection, e.g. between RL checkpoints), "
                        "or crowdnav: CrowdNav's own test cases (episode i = its case i, seed 1000 + i; the CrowdNav presets only, "
                        "at most 500 episodes)")
    parser.add_argument("--n-obstacles", type=int, help="obstacles of the random (default 8) and CrowdNav (default 5) presets")
    parser.add_argument("--workers", type=int, default=os.cpu_count(), help="parallel processes")
    parser.add_argument("--agent-kwargs", default="{}",
                        help='JSON overrides: for every agent, e.g. \'{"n_waypoints": 3}\', or per agent, e.g. \'{"pso": {"n_waypoints": 3}}\'')
    for name, what in ENV_OPTION_FLAGS.items():
        parser.add_argument(f"--{name}", help=f"{what}: every episode's env takes {name}=NAME")
        parser.add_argument(f"--{name}-params", help=f"JSON: its parameters, every episode's env takes {name}_params=...")
    parser.add_argument("--env-options", default="{}", help='JSON: gym.make keywords for every episode\'s env, e.g. \'{"observation": "state"}\'')
    parser.add_argument("--resume", action="store_true", help="continue the run recorded in --out/episodes.jsonl")
    parser.add_argument("--backend", choices=("process", "ray"), default="process",
                        help='where episodes run: a local process pool (--workers) or Ray (pip install -e ".[ray]")')
    parser.add_argument("--address", help="with --backend ray: a running cluster's address (default: a local Ray)")
    parser.add_argument("--out", default="results/latest", help="output directory")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--record", action="store_true",
                        help='keep every episode\'s trajectory in --out/episodes.h5 (replay: render --record; needs pip install -e ".[records]")')
    parser.add_argument("--no-limit", action="store_true",
                        help=f"skip the physical limit (by default {LIMIT_AGENT} runs on every cell's episodes too)")
    return parser


def parse_args(argv=None, prog: str | None = None) -> argparse.Namespace:
    args = build_parser(prog).parse_args(argv)
    defaults = SUITES[args.suite] if args.suite else SUITES["default"]
    for key in ("agents", "scenarios", "episodes"):
        if getattr(args, key) is None:
            setattr(args, key, defaults[key])
    if args.delta_d is None and args.suite:
        args.delta_d = defaults["delta_d"]  # else chosen in main, once the scenarios are known
    return args


def _entries(text: str) -> list[str]:
    return [entry.strip() for entry in text.split(",") if entry.strip()]


def _delta(text: str) -> float | None:
    if text.strip().lower() == OWN_SPEEDS:
        return None
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"--delta-d: expected comma-separated numbers or {OWN_SPEEDS!r}, got {text.strip()!r}") from None


def _json_flag(text: str, flag: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise SystemExit(f"{flag}: not valid JSON ({error}): {text!r}") from None


def _env_options(args: argparse.Namespace) -> dict:
    """``--env-options`` with the named flags merged in; a keyword given both ways is an error."""
    options = _json_flag(args.env_options, "--env-options")
    if not isinstance(options, dict):
        raise SystemExit(f"--env-options: expected a JSON object of gym.make keywords, got {args.env_options!r}")
    for name in ENV_OPTION_FLAGS:
        for key, flag, value in ((name, f"--{name}", getattr(args, name)),
                                 (f"{name}_params", f"--{name}-params", getattr(args, f"{name}_params"))):  # fmt: skip
            if value is None:
                continue
            if key in options:
                raise SystemExit(f"{flag}: {key} is in --env-options too; give it once")
            options[key] = _json_flag(value, flag) if key.endswith("_params") else value
    return options


def main(argv=None, prog: str | None = None) -> list[dict]:
    args = parse_args(argv, prog)
    from agents.evaluation import resolve_agents, resolve_scenarios
    from agents.evaluation.checks import resolve_deltas

    try:  # each message names its flag, in one line
        agent_specs = resolve_agents(_entries(args.agents), argument="--agents")
        scenarios = resolve_scenarios(_entries(args.scenarios), argument="--scenarios")
        if args.delta_d is None:  # a scene of one's own runs at its own speeds; presets sweep the default suite's Δd
            args.delta_d = OWN_SPEEDS if all(not isinstance(s.scenario, str) for s in scenarios) else SUITES["default"]["delta_d"]
            if args.split == "crowdnav":  # CrowdNav's cases at CrowdNav's speeds, as its suite runs them
                args.delta_d = SUITES["crowdnav"]["delta_d"]
        deltas = resolve_deltas([_delta(d) for d in args.delta_d.split(",")], "--delta-d")
    except ValueError as error:
        raise SystemExit(str(error)) from None
    if args.episodes < 1:
        raise SystemExit("--episodes must be >= 1")
    try:
        agent_kwargs = json.loads(args.agent_kwargs)
    except json.JSONDecodeError as error:
        raise SystemExit(f"--agent-kwargs: not valid JSON ({error}): {args.agent_kwargs!r}") from None
    env_options = _env_options(args)
    start = time.perf_counter()
    try:
        settings = EvaluationSettings(
            seed=args.seed, split=args.split, n_obstacles=args.n_obstacles, workers=args.workers,
            agent_kwargs=agent_kwargs, limit=not args.no_limit, resume=args.resume, plots=not args.no_plots,
            config={"suite": args.suite}, backend=args.backend, address=args.address, env_options=env_options,
            record=args.record,
        )  # fmt: skip
        rows = evaluate(agent_specs, scenarios, deltas, args.episodes, args.out, settings)
    except ValueError as error:  # named by the harness before any episode ran or anything was written
        raise SystemExit(f"{prog or 'evaluate.py'}: {error}") from None
    except KeyboardInterrupt:  # the harness has said what is on record (closed) and that --resume continues
        sys.stdout.flush(), sys.stderr.flush()
        os._exit(130)  # not SystemExit: exit would join the pool's manager thread, which workers killed mid-write can hang
    print(summary_tables(rows, [s.label for s in scenarios]))
    social = social_table(rows)  # a recorded run's (--record)
    if social:
        print("\n" + social)
    out = Path(args.out)
    config = json.loads((out / "summary.json").read_text())["config"]
    ran, before = config["episodes_run"], config["episodes_on_record"]
    seconds = time.perf_counter() - start
    counted = f"{ran} episode{'s' * (ran != 1)} ran in {seconds:.0f} s" + (f", {before} were on record: {ran + before} in all" if before else "")
    plots = "" if args.no_plots else ", plots"
    print(f"\nwrote {out / 'summary.json'}, {out / 'episodes.csv'}, {out / TABLE_NAME} (every cell), {out / 'report.html'}{plots} ({counted})")
    return rows

