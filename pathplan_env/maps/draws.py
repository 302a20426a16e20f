"""numpy's ``Generator`` draws made inside compiled code, bit for bit: ``integers(n, size=k)`` (for
``1 <= n <= 2**32``) and ``random(k)`` as numpy's own loops make them, through the generator's own C
functions (``bit_generator.ctypes``: ``next_uint32`` and ``next_double``, called through their
addresses, which travel as integers so that the compiled code caches). A sampler that draws and tests
candidates in one compiled call saves the Python calls' fixed cost (``integers`` ~6 µs a call, most of
a 64-point batch of the maze's free-space sampling). Like numpy's methods, the draws read and advance
the bit generator's state (its buffered 32-bit half included); unlike them they take no lock: a
generator is not shared between threads here. ``tests/maps/test_compiled_draws.py``: the same
values and the same state after, against numpy, over seeds, bounds and interleavings.
"""

from __future__ import annotations

import ctypes

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

#: The largest ``n`` of :func:`integers` (numpy's 32-bit path; larger bounds take its 64-bit one).
MAX_BOUND = 2**32


def bit_source(rng: np.random.Generator) -> tuple[int, int, int]:
    """``(state address, next_uint32's address, next_double's address)`` of ``rng``'s bit generator:
    what the compiled draws read (the ``ctypes`` interface is built once per bit generator)."""
    interface = rng.bit_generator.ctypes
    functions = _FUNCTIONS.get(type(rng.bit_generator))
    if functions is None:
        functions = (ctypes.cast(interface.next_uint32, ctypes.c_void_p).value, ctypes.cast(interface.next_double, ctypes.c_void_p).value)
        if type(rng.bit_generator).__module__.startswith("numpy.random"):  # (numpy's own: one C function per class)
            _FUNCTIONS[type(rng.bit_generator)] = functions
    return (interface.state_address, *functions)


_FUNCTIONS: dict[type, tuple[int, int]] = {}


@intrinsic
def _call_uint32(typingctx, function, state):
    """``((uint32_t (*)(void *)) function)(state)``."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.IntType(32), [pointer_t])
        return builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(args[1], pointer_t)])

    return types.uint32(types.int64, types.int64), codegen


@intrinsic
def _call_double(typingctx, function, state):
    """``((double (*)(void *)) function)(state)``."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.DoubleType(), [pointer_t])
        return builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(args[1], pointer_t)])

    return types.float64(types.int64, types.int64), codegen


@numba.njit(cache=True, inline="always")
def next_double(source):
    """One ``rng.random()`` (numpy's ``random_standard_uniform_fill`` draws one ``next_double`` a value)."""
    return _call_double(source[2], source[0])


@numba.njit(cache=True, inline="always")
def next_below(source, n):
    """One value of ``rng.integers(n)`` for ``1 <= n <= 2**32``: numpy's ``random_bounded_uint64_fill``
    for ``rng = n - 1`` below 2**32: 0 without a draw for ``n == 1``, a plain ``next_uint32`` for
    ``n == 2**32``, else ``buffered_bounded_lemire_uint32`` (Lemire's rejection, its threshold
    computed only when the first draw's low word is below ``n``)."""
    if n == 1:
        return np.int64(0)
    if n == MAX_BOUND:
        return np.int64(_call_uint32(source[1], source[0]))
    excl = np.uint64(n)  # rng + 1
    low_word = np.uint64(0xFFFFFFFF)
    m = np.uint64(_call_uint32(source[1], source[0])) * excl
    leftover = m & low_word
    if leftover < excl:
        threshold = (low_word - np.uint64(n - 1)) % excl  # (UINT32_MAX - rng) % rng_excl
        while leftover < threshold:
            m = np.uint64(_call_uint32(source[1], source[0])) * excl
            leftover = m & low_word
    return np.int64(m >> np.uint64(32))


@numba.njit(cache=True)
def integers(source, n, k):
    """``rng.integers(n, size=k)`` (int64) for ``1 <= n <= 2**32``."""
    out = np.empty(k, np.int64)
    for i in range(k):
        out[i] = next_below(source, n)
    return out


@numba.njit(cache=True)
def uniform(source, k):
    """``rng.random(k)``."""
    out = np.empty(k)
    for i in range(k):
        out[i] = next_double(source)
    return out


__all__ = ["MAX_BOUND", "bit_source", "integers", "next_below", "next_double", "uniform"]
