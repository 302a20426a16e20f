"""No compiled kernel takes more than 10 arguments: past that they come as named records
(``typing.NamedTuple``; from Python, the plain tuple of a record's fields, which numba types in C).

A kernel of 14 positional floats is where two arguments swap unnoticed; the records name them."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MAX_ARGUMENTS = 10


def _compiled(node: ast.FunctionDef) -> bool:
    return any("jit" in ast.unparse(decorator) for decorator in node.decorator_list)


def kernels() -> list[tuple[str, str, int]]:
    found = []
    for package in ("pathplan_env", "agents"):
        for path in sorted((ROOT / package).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.FunctionDef) and _compiled(node):
                    a = node.args
                    count = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + bool(a.vararg) + bool(a.kwarg)
                    found.append((str(path.relative_to(ROOT)), node.name, count))
    return found


def test_the_walk_finds_the_kernels():
    names = {name for _, name, _ in kernels()}
    assert {"scan_beams", "fly_substep", "_observation_row_carrying", "_orca_step_fields", "abc_run"} <= names


def test_no_kernel_takes_more_than_ten_arguments():
    wide = [f"{path}::{name} ({count})" for path, name, count in kernels() if count > MAX_ARGUMENTS]
    assert not wide, f"kernels past {MAX_ARGUMENTS} arguments (give them a NamedTuple record): {wide}"
