"""The documentation site builds as `make docs` builds it: every page, the environment's docstring and
the API reference, with warnings as errors, so a link to a page or heading that does not exist, a
page outside every toctree or a broken include fails here (external links are not checked)."""

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NEEDED = ("sphinx", "myst_parser", "furo")
MISSING = [name for name in NEEDED if importlib.util.find_spec(name) is None]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    if MISSING:
        pytest.skip(f"{', '.join(MISSING)} not installed: pip install -e .[docs] (make test installs it)")
    out = tmp_path_factory.mktemp("site")
    built = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(ROOT / "docs"), str(out)],
                           capture_output=True, text=True, timeout=900)  # fmt: skip
    assert built.returncode == 0, built.stderr[-4000:]
    return out


def test_the_site_builds_with_warnings_as_errors(site):
    assert (site / "index.html").exists() and (site / "environment.html").exists()


def test_the_environment_page_holds_the_class_docstring(site):
    import pathplan_env

    page = (site / "environment.html").read_text("utf-8")
    first = next(line.strip() for line in pathplan_env.DynamicObstacleEnv.__doc__.splitlines() if line.strip() and not line.strip().startswith("#"))
    assert first[:40] in re.sub(r"<[^>]+>", "", page), first[:40]


def test_every_internal_link_of_the_site_resolves(site):
    """The built pages' relative links all land on a file of the build, and their #anchors on an id
    of that page (sphinx -W checks the Markdown references; this checks what it wrote)."""
    broken = []
    ids = {}
    for page in site.rglob("*.html"):
        for href in re.findall(r'href="([^"#:?]*)(?:#([^"]*))?"', page.read_text("utf-8")):
            target, anchor = href
            if target.startswith(("//", "_static")) or "://" in target:
                continue
            path = (page.parent / target).resolve() if target else page
            if path.is_dir():
                path = path / "index.html"
            if not path.exists():
                broken.append((page.relative_to(site).as_posix(), target))
            elif anchor and path.suffix == ".html":
                if path not in ids:
                    ids[path] = set(re.findall(r'id="([^"]+)"', path.read_text("utf-8")))
                from urllib.parse import unquote

                if unquote(anchor) not in ids[path]:
                    broken.append((page.relative_to(site).as_posix(), f"{target}#{anchor}"))
    assert not broken, broken[:20]


def test_the_generated_pages_follow_the_code(site):
    """Written at every build: a family's page from the registry, every script's flags from its parser,
    a page a public module from its docstrings."""
    import agents
    from agents.cli import COMMANDS

    for family in agents.families():
        page = (site / "families" / f"{family}.html").read_text("utf-8")
        assert all(preset in page for preset, p in agents.presets().items() if p.family == family), family
    reference = re.sub(r"<[^>]+>", "", (site / "reference" / "scripts.html").read_text("utf-8"))
    for script in (ROOT / "scripts").glob("*.py"):
        assert f"python scripts/{script.name}" in reference, script.name
    assert all(f"pathplan-env {name}" in reference for name in COMMANDS) and "--delta-d" in reference
    for module in ("pathplan_env.env", "agents.registry", "agents.evaluation.harness"):
        assert (site / "api" / "generated" / f"{module}.html").exists(), module
