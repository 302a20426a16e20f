"""Render one episode of an agent to a GIF or MP4: ``pathplan-env render`` as a script, with the same flags (``--help``).

The command lives in ``agents/cli/render.py`` (its docstring is this command's help); this file keeps
``python scripts/render_episode.py ...`` working as every page of the documentation writes it.
"""

import sys

from agents.cli.render import build_parser, main, parse_args, save_gif

__all__ = ["build_parser", "main", "parse_args", "save_gif"]

if __name__ == "__main__":
    try:
        main()
    except ValueError as error:  # bad input, named by the library: one line, not a traceback
        sys.exit(f"render_episode.py: {error}")
