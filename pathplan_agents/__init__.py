"""pathplan-env's agents under a name no other package uses: ``import pathplan_agents as agents``.

The project's agents live in the top-level package ``agents`` (``agents.make``, ``agents.evaluation``).
Another distribution with a top-level ``agents`` (``openai-agents``) can shadow it on ``sys.path`` or
be merged into its folder by pip. This package loads ``agents`` from its own checkout's or install's
folder (the one beside this file) whatever ``import agents`` would find, and gives it back::

    import pathplan_agents as agents
    agent = agents.make("pso-spacetime", env, seed=0)
    from pathplan_agents import evaluation      # agents.evaluation

In a folder pip merged with another package's files it loads ours anyway (their files are never
imported by ours), and warns. It cannot help when the other package's ``agents`` was imported first
in the process (the name ``agents`` is taken), nor when pip wrote their ``__init__.py`` over ours: an
``ImportError`` then says so.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import sys
import warnings
from pathlib import Path

#: The folder of our ``agents``: beside this package, in a checkout and in site-packages alike.
FOLDER = Path(__file__).resolve().parent.parent / "agents"
#: While true, ``agents/__init__.py`` loads beside foreign files (``agents._ownership.check_ours``).
LOADING_OURS = False


def _load():
    global LOADING_OURS
    loaded = sys.modules.get("agents")
    if loaded is not None:
        if getattr(loaded, "PATHPLAN_ENV", False):
            return loaded
        raise ImportError(f"another package's `agents` ({getattr(loaded, '__file__', '?')}) was imported before pathplan_agents: "
                          "import pathplan_agents first, or keep the two packages in separate virtualenvs", name="pathplan_agents")  # fmt: skip
    init = FOLDER / "__init__.py"
    if not init.is_file() or "PATHPLAN_ENV = True" not in init.read_text(encoding="utf-8", errors="replace"):
        raise ImportError(f"{init} is not pathplan-env's (pip wrote another package's `agents/__init__.py` over it, e.g. openai-agents'): "
                          "pip uninstall openai-agents pathplan-env, then reinstall pathplan-env, or keep them in separate virtualenvs",
                          name="pathplan_agents")  # fmt: skip
    spec = importlib.util.spec_from_file_location("agents", init, submodule_search_locations=[str(FOLDER)])
    module = importlib.util.module_from_spec(spec)
    sys.modules["agents"] = module
    LOADING_OURS = True  # our code only, beside whatever else pip put in the folder
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules["agents"]
        raise
    finally:
        LOADING_OURS = False
    foreign = module._ownership.foreign_entries([FOLDER])
    if foreign:
        warnings.warn(f"pathplan_agents: {FOLDER} also holds files that are not pathplan-env's ({', '.join(p.name for p in foreign[:5])}); "
                      "ours are loaded, theirs ignored; `import agents` elsewhere refuses this folder", stacklevel=3)  # fmt: skip
    return module


_agents = _load()
sys.modules[__name__].__dict__.update({k: v for k, v in vars(_agents).items() if not k.startswith("__")})
__all__ = list(getattr(_agents, "__all__", []))


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """``pathplan_agents.X`` is ``agents.X``, the same module object (not a second copy of its classes)."""

    def find_spec(self, fullname, path, target=None):
        if fullname.startswith(__name__ + "."):
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        return importlib.import_module("agents" + spec.name[len(__name__) :])

    def exec_module(self, module):
        pass  # agents.X ran when it was imported


if not any(isinstance(finder, _Alias) for finder in sys.meta_path):
    sys.meta_path.insert(0, _Alias())


def __getattr__(name: str):
    return getattr(_agents, name)
