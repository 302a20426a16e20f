"""Sphinx configuration of pathplan-env's documentation site (``make docs``)."""

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
source_suffix = {".md": "markdown"}
myst_heading_anchors = 4  # GitHub-style anchors, so the pages' [text](page.md#heading) links resolve
myst_enable_extensions = ["colon_fence"]
exclude_patterns = ["_build"]
autodoc_member_order = "bysource"
autosummary_generate = False
# the docstrings' "``x``" is code, as in the README; nitpicky cross-references to typing aliases would
# only warn
nitpicky = False


def _gymnasium_headings(app, what, name, obj, options, lines):
    """Gymnasium's docstrings title their parts with Markdown headings (``## Description``): make them
    reST rubrics, which autodoc can place inside a class's body."""
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


def setup(app):
    app.connect("autodoc-process-docstring", _gymnasium_headings)
    app.connect("source-read", _environment_docstring)
