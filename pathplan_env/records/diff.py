"""Do two runs' records hold the same trajectories? Episodes are matched by the harness's job key;
the robot's and the obstacles' states compared exactly, and the first step where they part named."""

from __future__ import annotations

import numpy as np

from pathplan_env.records.store import open_records


def first_difference(a, b) -> int | None:
    """The first row where two episodes' robot or obstacles differ (None: the same throughout)."""
    rows = min(len(a.robot), len(b.robot))
    same = np.all(a.robot[:rows] == b.robot[:rows], axis=1) & np.all((a.obstacles[:rows] == b.obstacles[:rows]).reshape(rows, -1), axis=1)
    if not same.all():
        return int(np.argmin(same))
    return None if len(a.robot) == len(b.robot) else rows


def diff_records(first, second) -> tuple[int, list[str]]:
    """How many episodes both runs recorded, and a line for each that differs or is in one run only."""
    with open_records(first) as a, open_records(second) as b:
        keys_a, keys_b = a.header_keys(), b.header_keys()
        where_b = {key: number for number, key in enumerate(keys_b)}
        lines, both = [], 0
        for number, key in enumerate(keys_a):
            if key not in where_b:
                lines.append(f"record {number} of {a.path} ({_name(a.meta(number))}) is not in {b.path}")
                continue
            both += 1
            step = first_difference(a.episode(number), b.episode(where_b[key]))
            if step is not None:
                lines.append(f"{_name(a.meta(number))}: the trajectories part at step {step} (records {number} and {where_b[key]})")
        lines += [f"record {where_b[k]} of {b.path} ({_name(b.meta(where_b[k]))}) is not in {a.path}" for k in keys_b if k not in set(keys_a)]
    return both, lines


def _name(meta: dict) -> str:
    return f"{meta['agent']} on {meta['scenario']}, Δd {meta['delta_d']}, episode {meta['episode']}"
