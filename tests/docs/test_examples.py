"""The site cannot drift from the code: every Python block of the getting-started page and the
tutorials runs, page by page in one namespace (as a reader pastes them in order), from a scratch
folder; and every docstring example (``>>>``) of the two packages passes as a doctest.

A block preceded by ``<!-- slow: why -->`` runs only with the slow tests (``-m slow``), and one preceded
by ``<!-- not run: why -->`` never does (the page says what runs it instead). The README's quick start
is run by tests/packaging/test_wheel.py, on the installed wheel; docs/your_agent.md's files by
tests/test_readme.py."""

import doctest
import importlib
import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = ["getting_started.md", *sorted(p.relative_to(ROOT / "docs").as_posix() for p in (ROOT / "docs" / "tutorials").glob("*.md"))]
BLOCK = re.compile(r"(?:<!-- (slow|not run): [^>]*-->\n)?```python\n(.*?)```", re.S)
#: what a page's blocks need beyond the core install, and the extra that gives it
NEEDS = {"tutorials/sb3_vecnormalize.md": ("stable_baselines3", "rl"), "tutorials/ray.md": ("ray", "ray")}


def blocks(page: str) -> list[tuple[str | None, str]]:
    return [(m.group(1), m.group(2)) for m in BLOCK.finditer((ROOT / "docs" / page).read_text("utf-8"))]


def _params():
    for page in PAGES:
        marks = [pytest.mark.slow] if any(kind == "slow" for kind, _ in blocks(page)) else []
        yield pytest.param(page, marks=marks, id=page)


def test_every_tutorial_has_a_block_to_run():
    assert len(PAGES) >= 6
    for page in PAGES:
        assert [code for kind, code in blocks(page) if kind != "not run"], page


@pytest.mark.parametrize("page", list(_params()))
def test_the_python_blocks_of_a_page_run(page, tmp_path, monkeypatch, capsys):
    module, extra = NEEDS.get(page, (None, None))
    if module and importlib.util.find_spec(module) is None:
        pytest.skip(f"{page} needs {module}: pip install -e .[{extra}]")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__main__"}
    for number, (kind, code) in enumerate(blocks(page), 1):
        if kind == "not run":
            continue
        page_code = code
        if page == "getting_started.md":  # the quick start's harness call: 20 episodes of three agents is the slow tests' job
            page_code = code.replace("episodes=20", "episodes=1, plots=False").replace("n_eval_episodes=10", "n_eval_episodes=1")
        exec(compile(page_code, f"docs/{page}, block {number}", "exec"), namespace)
    assert capsys.readouterr().out.strip(), "a tutorial's blocks print what they show"


def _modules_with_examples() -> list[str]:
    names = []
    for package in ("pathplan_env", "agents"):
        for path in sorted((ROOT / package).rglob("*.py")):
            if ">>> " in path.read_text("utf-8"):
                names.append(".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__"))
    return names


def test_the_packages_have_docstring_examples():
    assert len(_modules_with_examples()) >= 3


@pytest.mark.parametrize("name", _modules_with_examples())
def test_the_docstring_examples_pass(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 0 and result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed (run python -m doctest -v)"
