"""The agent tables of the README and ``docs/agents.md``, written from the registry between
markers (``python scripts/agent_tables.py``; a test checks the committed ones are current)."""

from __future__ import annotations

from agents.planners.spacetime import astar_agent as spacetime_astar
from agents.planners.spacetime import metaheuristic_agent as spacetime_metaheuristic
from agents.planners.unicycle import astar_agent as unicycle_astar
from agents.planners.unicycle import metaheuristic_agent as unicycle_metaheuristic
from agents.registry import families, presets, robots_of

#: What ``tuning="crowd"`` sets, by family and plan: the constants the factories read.
CROWD_TUNINGS = (
    ("pso, abc", "spacetime", spacetime_metaheuristic.CROWD_SETTINGS),
    ("pso, abc", "controls", unicycle_metaheuristic.CROWD_SETTINGS),
    ("astar", "spacetime", spacetime_astar.CROWD_SETTINGS),
    ("astar", "controls", unicycle_astar.CROWD_SETTINGS),
)


def _settings(parameters) -> str:
    return ", ".join(f"`{key}={value!r}`" for key, value in parameters.items()) or "(defaults)"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")  # a pipe inside a cell would end it


def family_table() -> str:
    """The README's table: one row per family, what it is and its presets."""
    rows = ["| family | what | presets |", "|---|---|---|"]
    named = {}
    for name, preset in presets().items():
        named.setdefault(preset.family, []).append(f"`{name}`")
    for name, family in families().items():
        rows.append(f"| `{name}` | {_cell(family.summary)} | {', '.join(named.get(name, [])) or '—'} |")
    return "\n".join(rows) + "\n"


def parameter_table() -> str:
    """One row per family: the parameters that choose what it is, and the robots it drives."""
    rows = ["| family | parameters that choose it | robot |", "|---|---|---|"]
    for name, family in families().items():
        axes = "; ".join(f"`{axis}`: {meaning}" for axis, meaning in family.axes.items()) or "—"
        rows.append(f"| `{name}` | {_cell(axes)} | {', '.join(family.every_robot)} |")
    return "\n".join(rows) + "\n"


def preset_table() -> str:
    """One row per preset: its family, the parameters it sets, its robot and note."""
    rows = ["| preset | family | parameters | robot | note |", "|---|---|---|---|---|"]
    for name, preset in presets().items():
        rows.append(f"| `{name}` | `{preset.family}` | {_cell(_settings(preset.parameters))} | {', '.join(robots_of(name))} | {_cell(preset.note)} |")
    return "\n".join(rows) + "\n"


def tuning_table() -> str:
    """What ``tuning="crowd"`` sets for each family and plan."""
    rows = ["| family | plan | `tuning=\"crowd\"` sets |", "|---|---|---|"]
    rows += [f"| {family} | `{plan}` | {_settings(settings)} |" for family, plan, settings in CROWD_TUNINGS]
    return "\n".join(rows) + "\n"


#: The generated sections by marker: ``<!-- agent families: scripts/agent_tables.py -->`` ... ``<!-- end of agent families -->``.
SECTIONS = {"agent families": family_table, "agent parameters": parameter_table, "agent presets": preset_table, "agent tunings": tuning_table}


def filled(text: str, source: str) -> str:
    """``text`` (a Markdown page, named ``source`` in errors) with every marked section written anew."""
    for marker, table in SECTIONS.items():
        begin, end = f"<!-- {marker}: scripts/agent_tables.py -->\n", f"<!-- end of {marker} -->\n"
        if begin not in text:
            continue
        head, rest = text.split(begin, 1)
        if end not in rest:
            raise ValueError(f"{source}: {begin.strip()} without {end.strip()}")
        text = head + begin + table() + end + rest.split(end, 1)[1]
    return text


def family_page(name: str) -> str:
    """The documentation page of one family (``docs/families/NAME.md``, written at every build): what it is,
    the parameters that choose it, its robots, how it is made, and its presets."""
    import inspect

    family = families()[name]
    own = {preset_name: preset for preset_name, preset in presets().items() if preset.family == name}
    lines = [f"# `{name}`", "", f"{family.summary[:1].upper()}{family.summary[1:]}." if family.summary else "", ""]
    lines += [f"Robots: {', '.join(family.every_robot)}. Made by `agents.make({name!r}, env, seed=None, **parameters)`, "
              f"its factory `{family.factory.__module__}.{family.factory.__qualname__}`:", ""]
    try:
        signature = str(inspect.signature(family.factory))
    except (TypeError, ValueError):
        signature = "(env, seed=None, **parameters)"
    lines += ["```python", f"{family.factory.__qualname__}{signature}", "```", ""]
    if family.axes:
        lines += ["## Parameters that choose it", "", "| parameter | what it chooses |", "|---|---|"]
        lines += [f"| `{axis}` | {_cell(meaning)} |" for axis, meaning in family.axes.items()] + [""]
    lines += ["## Presets", ""]
    if own:
        lines += ["| preset | parameters | robot | note |", "|---|---|---|---|"]
        lines += [f"| `{p}` | {_cell(_settings(preset.parameters))} | {', '.join(robots_of(p))} | {_cell(preset.note)} |" for p, preset in own.items()]
    else:
        lines += ["None: the family's own name is the agent."]
    return "\n".join(lines) + "\n"
