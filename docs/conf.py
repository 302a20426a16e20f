"""Sphinx configuration of pathplan-env's documentation site (``make docs``)."""

import importlib.util
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

project = "pathplan-env"
author = "pathplan-env contributors"
copyright = "2026, pathplan-env contributors"
release = "0.2.0.dev0"

# MyST-Parser: the pages stay Markdown, as the repository's README and results always were;
# furo: the theme that Stable-Baselines3- and Gymnasium-style projects' sites use.
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.napoleon"]
html_theme = "furo"
html_title = "pathplan-env"
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}  # .rst: the API pages autosummary writes
myst_heading_anchors = 4  # GitHub-style anchors, so the pages' [text](page.md#heading) links resolve
myst_enable_extensions = ["colon_fence"]
exclude_patterns = ["_build"]
autodoc_member_order = "bysource"
autodoc_inherit_docstrings = False  # Gymnasium's own step/reset docstrings are Google-style, not ours
autosummary_generate = True  # the API reference's pages (docs/api/, written at every build, not committed)
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
# the docstrings' "``x``" is code, as in the README; nitpicky cross-references to typing aliases would
# only warn
nitpicky = False


def _gymnasium_headings(app, what, name, obj, options, lines):
    """Gymnasium's docstrings title their parts with Markdown headings (``## Description``): make them
    reST rubrics, which autodoc can place inside a class's body; their Markdown tables become literal
    blocks (reST reads a ``|`` line as a line block). The env's own docstring, Markdown throughout, is
    rendered as Markdown on the environment page and pointed to from here."""
    if name == "pathplan_env.env.DynamicObstacleEnv" or name == "pathplan_env.DynamicObstacleEnv":
        lines[:] = ["Gymnasium's ``DynamicObstacle-v0``. Its docstring, in Markdown as Gymnasium's envs write theirs,",
                    "is the :doc:`environment page </environment>`.", ""]
        return
    out, in_table = [], False
    for line in lines:
        row = line.lstrip().startswith("|")
        if row and not in_table:
            out += ["", "::", ""] if out and out[-1].strip() else ["::", ""]
        elif not row and in_table and line.strip():
            out.append("")
        out.append("    " + line if row else line)
        in_table = row
    lines[:] = out
    for i, line in enumerate(lines):
        match = re.match(r"^\s*#{2,4} (.+)$", line)
        if match:
            lines[i] = f".. rubric:: {match.group(1)}"
            if i + 1 < len(lines) and lines[i + 1].strip():
                lines.insert(i + 1, "")


def _environment_docstring(app, docname, source):
    """environment.md holds ``DynamicObstacleEnv.__doc__`` as the class has it, read at every build.
    The docstring is written in Gymnasium's Markdown (its headings, its tables), so it is given to
    MyST as Markdown, its headings one level under the page's title."""
    if docname != "environment":
        return
    import inspect

    from pathplan_env import DynamicObstacleEnv

    text = inspect.getdoc(DynamicObstacleEnv)
    source[0] = source[0].replace("<!-- DynamicObstacleEnv.__doc__ -->", text)


def _write_if_changed(path: Path, text: str) -> None:
    """Write a generated page only when it changed, so an incremental build rereads only what moved."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text("utf-8") != text:
        path.write_text(text, "utf-8")


def _family_pages() -> None:
    """One page a family, its presets from the registry (``agents.tables.family_page``), as Gymnasium
    writes one page an env from the registry: docs/families/ is written here, never by hand."""
    import agents
    from agents.tables import family_page

    folder = ROOT / "docs" / "families"
    names = list(agents.families())
    index = ["# Agent families", "", "One page a family of the registry (`agents.families()`), written from it at every build: what",
             "the family is, the parameters that choose it and its presets. The tables of every preset are on",
             "[the agents page](../agents.md).", "", "```{toctree}", ":maxdepth: 1", "", *names, "```", ""]
    _write_if_changed(folder / "index.md", "\n".join(index))
    for name in names:
        _write_if_changed(folder / f"{name}.md", family_page(name))
    for stale in folder.glob("*.md"):
        if stale.stem not in names and stale.stem != "index":
            stale.unlink()


def _script_reference() -> None:
    """docs/reference/scripts.md: ``pathplan-env`` and every script's ``--help``, from their parsers
    (each script's ``build_parser()``), so a flag added or renamed shows here at the next build."""
    from agents.cli import COMMANDS, build_parser, command_parser

    os.environ["COLUMNS"] = "110"  # argparse wraps at the terminal's width: one width for every build
    parts = ["# Command-line reference", "",
             "Written at every build from the argument parsers themselves (`build_parser()` of `agents/cli/` and of",
             "each script in `scripts/`): what `--help` prints. `pathplan-env` is the console command a",
             "`pip install` gives; the scripts its subcommands wrap take the same flags.", "",
             "## `pathplan-env`", "", "```text", build_parser().format_help().rstrip(), "```", ""]
    for name in COMMANDS:
        parts += [f"### `pathplan-env {name}`", "", "```text", command_parser(name).format_help().rstrip(), "```", ""]
    parts += ["## The scripts", ""]
    sys.path.insert(0, str(ROOT / "scripts"))
    for script in sorted((ROOT / "scripts").glob("*.py")):
        spec = importlib.util.spec_from_file_location(f"_docs_script_{script.stem}", script)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        parser = module.build_parser()
        parser.prog = f"python scripts/{script.name}"
        parts += [f"### `scripts/{script.name}`", "", "```text", parser.format_help().rstrip(), "```", ""]
    _write_if_changed(ROOT / "docs" / "reference" / "scripts.md", "\n".join(parts))


_family_pages()
_script_reference()


def setup(app):
    app.connect("autodoc-process-docstring", _gymnasium_headings)
    app.connect("source-read", _environment_docstring)
