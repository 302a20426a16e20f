"""Which call steps a crowd among walls (``step_kernel.world_step_routed``): its compiled entry point
where the arguments have exactly its signature's types, else numba's dispatcher, which types its
30-odd arguments at every call (a tenth of a wall crowd's step)."""

from __future__ import annotations

import numpy as np

from pathplan_env.world import step_kernel


def routed_entry():
    """The routed step's entry point (``step_kernel.world_step_routed_entry``), made by the first world
    that steps a crowd among walls."""
    global routed_step
    if routed_step is None:
        routed_step = step_kernel.world_step_routed_entry()
    return routed_step


routed_step = None  # the routed step's entry point, once made


def contiguous(statics) -> bool:
    """Whether every array the routed compiled step reads of ``statics`` is C-contiguous."""
    arrays = (*statics.routes_fields, *statics.obstacle_fields, statics.scratch_targets, statics.missing)
    return all(a.flags.c_contiguous for a in arrays if isinstance(a, np.ndarray))


def routed_typed(statics, fresh: bool = False) -> bool:
    """Whether the routed step's arguments of ``statics`` have exactly the types of its entry point's
    signature (``step_kernel.ROUTED_SIGNATURE``: numbers of those Python types, arrays of those dtypes and
    dimensions, C-contiguous, aligned and writable): the entry point unboxes them without checking.
    The arrays a geometry's worlds share (its grid's, its RVO2 obstacles') are checked once (kept by identity);
    ``fresh``: ``statics`` is ``routing.human_statics``' own, whose other arrays it has just made with
    the signature's dtypes and dimensions, C-contiguous and writable (not checked again)."""
    routes, obstacles = statics.routes_fields, statics.obstacle_fields
    if len(routes) != len(_ROUTES_KINDS) or len(obstacles) != len(_OBSTACLES_KINDS):
        return False
    for k, (value, (kind, ndim)) in enumerate(zip(routes, _ROUTES_KINDS)):
        if ndim is None:
            if type(value) is not kind:
                return False
        elif k in _SHARED_ROUTES:
            if _SHARED_TYPED.get(id(value)) is not value:
                if not _array_typed(value, kind, ndim):
                    return False
                _remember(value)
        elif not (fresh or _array_typed(value, kind, ndim)):
            return False
    for value, (kind, ndim) in zip(obstacles, _OBSTACLES_KINDS):
        if _SHARED_TYPED.get(id(value)) is not value:
            if not _array_typed(value, kind, ndim):
                return False
            _remember(value)
    return fresh or (_array_typed(statics.scratch_targets, _FLOAT64, 2) and _array_typed(statics.missing, _INT64, 1))


def _array_typed(value, dtype, ndim) -> bool:
    # (numpy's flag bits in one read: C-contiguous 0x1, aligned 0x100, writeable 0x400; an array numba made
    # has a dtype equal to numpy's, not numpy's own object)
    if type(value) is not np.ndarray or value.ndim != ndim or not (value.dtype is dtype or value.dtype == dtype):
        return False
    return value.flags.num & 0x501 == 0x501


def _remember(array) -> None:
    if len(_SHARED_TYPED) >= 64:  # (a few geometries' worth; more: checked again)
        _SHARED_TYPED.clear()
    _SHARED_TYPED[id(array)] = array


_FLOAT64, _INT64 = np.dtype(np.float64), np.dtype(np.int64)
_ROUTES_KINDS = tuple((kind, None) if ndim is None else (np.dtype(kind), ndim) for kind, ndim in step_kernel.ROUTES_KINDS)
_OBSTACLES_KINDS = tuple((np.dtype(kind), ndim) for kind, ndim in step_kernel.OBSTACLES_KINDS)
_SHARED_ROUTES = frozenset({5, 6, 11})  # Routes.free, nearest, blocked_below: the grid's (routing._grid, cached per geometry)
_SHARED_TYPED: dict[int, np.ndarray] = {}  # id -> a shared array found typed (kept, so that its id stays its own)
