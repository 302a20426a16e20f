"""scripts/bench_families.py --against: the copy's named tuples must not collide with ours in numba's dispatch."""

import importlib
import sys
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
bench_families = importlib.import_module("bench_families")

SOURCE = "from typing import NamedTuple\nimport numpy as np\n\nclass Queue(NamedTuple):\n    width: float\n    ring: np.ndarray\n"


def _package(root: Path, name: str):
    (root / name).mkdir()
    (root / name / "__init__.py").write_text("")
    (root / name / "queue.py").write_text(SOURCE)
    return importlib.import_module(name)


def test_the_copys_named_tuples_are_typed_on_numbas_fast_path(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))
    _package(tmp_path, "bias_ours")
    before = _package(tmp_path, "bias_before")
    bench_families.distinguish_named_tuples(before)
    Ours, Before = importlib.import_module("bias_ours.queue").Queue, importlib.import_module("bias_before.queue").Queue
    assert (Ours.__name__, Before.__name__) == ("Queue", "Queue_before")

    def kernel(q):
        return q.ring[0] + q.width

    first, second = numba.njit(kernel), numba.njit(kernel)
    first(Ours(1.0, np.zeros(3)))
    second(Before(1.0, np.zeros(3)))
    slow = []  # (the dispatcher's Python path: taken when the C cache returns the other class's type)
    monkeypatch.setattr(type(second), "_compile_for_args", lambda self, *a, **k: slow.append(a) or first.py_func(*a))
    assert second(Before(2.0, np.zeros(3))) == 2.0
    assert slow == []
