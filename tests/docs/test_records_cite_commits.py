"""The records speak of versions, commits and dates, never of how the work was scheduled: no page,
docstring, script or shipped model's sidecar names a session by its number, and no run-record folder is named after
one (``runs_s12``): a reader can check a version or a commit (``git show fc33d36``), not a session."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TREES = ("README.md", "CHANGELOG.md", "docs", "agents", "pathplan_env", "scripts")
SESSION = re.compile(r"\bsession[ -]\d|\bsession's\b|\bsessions\b|\b(?:this|last|next) session\b", re.IGNORECASE)
SESSION_FOLDER = re.compile(r".+_s\d+")
TEXT = {".md", ".py", ".json", ".txt", ".yaml", ".yml", ".toml", ".csv", ".log", ".rst", ".cfg"}


def _files():
    for tree in TREES:
        path = ROOT / tree
        if path.is_file():
            yield path
        else:
            yield from (p for p in path.rglob("*") if p.is_file() and p.suffix in TEXT and "_build" not in p.parts)


def test_no_record_says_session():
    found = []
    for path in _files():
        for number, line in enumerate(path.read_text("utf-8", errors="replace").splitlines(), 1):
            if SESSION.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:120]}")
    assert not found, "\n".join(found[:20])


def test_no_folder_is_named_after_a_session():
    folders = [p for tree in TREES if (ROOT / tree).is_dir() for p in (ROOT / tree).rglob("*") if p.is_dir()]
    named = [p.relative_to(ROOT).as_posix() for p in folders if SESSION_FOLDER.fullmatch(p.name) and "_build" not in p.parts]
    assert not named, named


def test_the_patterns_catch_what_they_are_for():
    word = "session"  # the phrases are built here so that this file does not hold them itself
    assert SESSION.search(f"chosen in {word.title()} 17") and SESSION.search(f"the {word}-14 models") and SESSION.search(f"this {word}")
    assert not SESSION.search("defined in an interactive session, which")
    assert SESSION_FOLDER.fullmatch("runs_s12") and not SESSION_FOLDER.fullmatch("test_random_seed12")
