"""A numba function's compiled entry point for one signature, called without its dispatcher.

A dispatcher call types every argument before it runs the machine code, a visible part of a small
crowd env's step (``scripts/bench_crowds.py --env-split``); the entry point of a known signature
skips that. It unboxes the arguments as that signature's types without checking them,
so a caller passes it only arguments of exactly those types (else the dispatcher).
"""

from __future__ import annotations


def entry_point(dispatcher, signature: tuple):
    """``dispatcher``'s entry point for ``signature`` (compiled, or loaded from numba's cache, now)."""
    dispatcher.compile(signature)
    return dispatcher.overloads[tuple(signature)].entry_point
