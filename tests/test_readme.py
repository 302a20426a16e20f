"""Every command the README and the documentation site give runs as written: its script exists and
accepts its flags, its agents and presets exist, its make targets exist. The README is the front door
(the set-up commands, the quick start); the rest moved to docs/*.md, and the checks followed it there."""

import importlib
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
#: the front door and the site's pages written from it (the results' own pages are run records, not instructions)
MOVED = ("getting_started", "your_agent", "environment", "world", "robots", "observations", "scenarios", "maps", "crowds",
         "rewards", "seeding", "agents", "results/index", "benchmarks", "reproducing", "architecture", "limitations",
         *(f"tutorials/{page.stem}" for page in sorted((ROOT / "docs" / "tutorials").glob("*.md"))))
PAGES = {"README.md": README, **{f"docs/{name}.md": (ROOT / "docs" / f"{name}.md").read_text("utf-8") for name in MOVED}}
SCRIPT_COMMAND = re.compile(r"(?:\.venv/bin/)?python (scripts/[\w]+\.py)((?: (?:'[^']*'|\"[^\"]*\"|[^\s`|']+))*)")


def readme_commands() -> list[tuple[str, str]]:
    found = {(m.group(1), m.group(2).strip()) for text in PAGES.values() for m in SCRIPT_COMMAND.finditer(text)}
    return sorted(found)


def test_the_readme_starts_with_the_two_set_up_commands():
    first_block = README.split("```")[1]
    assert "make demo" in first_block and "make test" in first_block
    targets = set(re.findall(r"^([\w-]+):", (ROOT / "Makefile").read_text(), re.M))
    for page, text in PAGES.items():
        assert set(re.findall(r"\bmake (\w+)", text)) <= targets, page


def test_the_readme_is_one_screen_and_links_the_site():
    assert len(README.encode("utf-8")) <= 15_000
    for page in re.findall(r"\]\((docs/[^)#\s]+|CHANGELOG\.md)", README):
        assert (ROOT / page).exists(), page


def test_the_readme_and_the_site_name_many_commands():
    assert len(readme_commands()) >= 10
    reproducing = PAGES["docs/reproducing.md"]
    assert len({m.group(1) for m in SCRIPT_COMMAND.finditer(reproducing)}) >= 10  # every figure's command


@pytest.mark.parametrize("script, arguments", readme_commands())
def test_readme_command_parses(script, arguments):
    import agents
    import pathplan_env
    from pathplan_env.multi_robot.presets import PRESETS as MULTI_ROBOT_PRESETS

    assert (ROOT / script).exists(), script
    sys.path.insert(0, str(ROOT / "scripts"))
    module = importlib.import_module(Path(script).stem)
    argv = [a.replace("...", "agents/models/ppo.zip") for a in shlex.split(arguments)]
    if not hasattr(module, "parse_args"):  # scripts/agent_tables.py: no arguments here, its run is tests/agents/test_families.py's
        assert not argv and callable(module.main), script
        return
    parsed = module.parse_args(argv)  # argparse exits on an unknown flag or a bad value
    # registered names and presets must exist; a user's own entries (module:Class, name@model, label=entry,
    # scene files) are run as written by test_benchmark_your_own_runs_as_written
    own = re.compile(r"[:@=]|\.(json|ya?ml)$")
    for name in ("agents", "agent"):
        for agent in str(getattr(parsed, name, "") or "").split(","):
            assert not agent or own.search(agent) or agent in agents.available(), (script, agent)
    scenarios = getattr(parsed, "scenarios", getattr(parsed, "scenario", "")) or ""
    for scenario in scenarios if isinstance(scenarios, list) else str(scenarios).split(","):
        known = scenario in pathplan_env.PRESETS or scenario in MULTI_ROBOT_PRESETS  # (the multi-robot scripts' scenes)
        assert not scenario or own.search(scenario) or known, (script, scenario)


@pytest.mark.slow
def test_the_quick_start_runs_as_written(tmp_path):
    # a stranger pastes it into a fresh directory: it must run there without a traceback
    block = README.split("## Quick start", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    out = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    first, rows = out.stdout.strip().splitlines()[-2:]
    assert first.split()[0] in ("True", "False") and "pso-spacetime" in rows
    assert (tmp_path / "results" / "mine" / "summary.json").exists()


def _blocks(section: str, language: str) -> list[str]:
    return [block.split("\n", 1)[1] for block in section.split("```")[1::2] if block.startswith(language)]


@pytest.mark.slow
def test_benchmark_your_own_runs_as_written(tmp_path):
    """The site's "Benchmark your own agent" (docs/your_agent.md): its scene file and agent module
    written where it says, then its Python run and its command line, in a fresh directory."""
    import json

    section = PAGES["docs/your_agent.md"].split("# Benchmark your own agent", 1)[1].split("\n## ", 1)[0]
    (scene,), (module,), (command,) = _blocks(section, "yaml"), _blocks(section, "python"), _blocks(section, "bash")
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "crossing.yaml").write_text(scene)
    (tmp_path / "pf_agent.py").write_text(module)
    env = {**__import__("os").environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "pf_agent.py"], cwd=tmp_path, capture_output=True, text=True, timeout=900, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    printed = {tuple(line.split()[:2]) for line in out.stdout.splitlines()}
    assert {("PotentialField", "random"), ("PotentialField", "crossing"), ("velocity-obstacle", "crossing")} <= printed
    argv = shlex.split(command.strip().replace("python scripts/", str(ROOT / "scripts") + "/", 1))
    out = subprocess.run([sys.executable, *argv], cwd=tmp_path, capture_output=True, text=True, timeout=900, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    rows = json.loads((tmp_path / "results" / "pf" / "summary.json").read_text())["results"]
    labels = {(row["agent"], row["scenario"]) for row in rows}
    assert ("pf_agent:PotentialField", "crossing") in labels and ("oracle-clairvoyant", "crossing") in labels


CONSOLE_COMMAND = re.compile(r"pathplan-env (\w+)((?: (?:'[^']*'|\"[^\"]*\"|[^\s`|'.][^\s`|']*))*)")


def console_commands() -> list[tuple[str, str]]:
    found = {(m.group(1), m.group(2).strip()) for text in PAGES.values() for m in CONSOLE_COMMAND.finditer(text)}
    return sorted(found)


def test_the_pages_name_the_console_command():
    assert {name for name, _ in console_commands()} >= {"evaluate", "render", "bench", "compare"}


@pytest.mark.parametrize("name, arguments", console_commands())
def test_console_command_parses(name, arguments):
    """``pathplan-env NAME ...`` as the README and the site write it: the subcommand exists and its
    parser (the same as the script's) takes the flags."""
    from agents.cli import COMMANDS, command_parser

    assert name in COMMANDS, name
    argv = [a for a in shlex.split(arguments) if a != "..."]
    if name == "compare" and len(argv) < 2:
        argv = ["a", "b"]
    command_parser(name).parse_args(argv)
