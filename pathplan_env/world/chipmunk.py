"""pymunk driven through Chipmunk directly, where pymunk's Python layers cost a reset or a step
too much: bodies and shapes added and removed with pymunk's bookkeeping mirrored, a batch buffer
that frees its C arrays, and the C functions the world calls every substep. Tested against pymunk's
own views (``tests/env/test_sturdy.py``: recycled worlds keep pymunk's bookkeeping)."""

from __future__ import annotations

import weakref

import numba
import pymunk
import pymunk.batch
from llvmlite import ir
from numba import types
from numba.extending import intrinsic
from pymunk._util import _dead_ref

_batch = pymunk.batch  # its ffi and lib
space_step, each_body, set_mass, set_radius = _batch.lib.cpSpaceStep, _batch.lib.cpSpaceEachBody, _batch.lib.cpBodySetMass, _batch.lib.cpCircleShapeSetRadius
add_body, add_shape = _batch.lib.cpSpaceAddBody, _batch.lib.cpSpaceAddShape
remove_body, remove_shape = _batch.lib.cpSpaceRemoveBody, _batch.lib.cpSpaceRemoveShape
set_shape_counter, set_time_step, set_slop = _batch.lib.cpSpaceSetShapeIDCounter, _batch.lib.cpSpaceSetCurrentTimeStep, _batch.lib.cpSpaceSetCollisionSlop
get_stamp = _batch.lib.cpSpaceGetTimestamp
READ_BODY = _batch.ffi.addressof(_batch.lib, "pmSpaceBodyGetIteratorFuncBatched")
WRITE_BODY = _batch.ffi.addressof(_batch.lib, "pmSpaceBodySetIteratorFuncBatched")
ffi = _batch.ffi


def space_add(space: pymunk.Space, objects) -> None:
    """``space.add(*objects)`` for bodies and shapes new to it, in the same order (bodies first), with
    pymunk's bookkeeping mirrored but without its per-object checks and property layers: adding
    and removing were a fifth of a reset. Nothing is added while the space steps."""
    ref, c_space = weakref.ref(space), space._space
    for body in objects:
        if isinstance(body, pymunk.Body):
            object.__setattr__(body, "_space", ref)
            space._bodies[body] = None
            space._bodies_to_check.add(body)
            add_body(c_space, body._body)
    for shape in objects:
        if not isinstance(shape, pymunk.Body):
            object.__setattr__(shape, "_space", ref)
            space._shapes[shape] = None
            add_shape(c_space, shape._shape)


def space_remove(space: pymunk.Space, objects) -> None:
    """``space.remove(*objects)`` (in order) for objects in the space, as :func:`space_add` adds them."""
    c_space = space._space
    for o in objects:
        object.__setattr__(o, "_space", _dead_ref)
        if isinstance(o, pymunk.Body):
            space._bodies_to_check.discard(o)
            remove_body(c_space, o._body)
            del space._bodies[o]
        else:
            space._removed_shapes[o] = None
            remove_shape(c_space, o._shape)
            del space._shapes[o]


def add_shapes(space: pymunk.Space, shapes) -> None:
    """:func:`space_add` for shapes alone, their bodies already in the space (a lent space's obstacles)."""
    ref, c_space, book, set_ = weakref.ref(space), space._space, space._shapes, object.__setattr__
    for shape in shapes:
        set_(shape, "_space", ref)
        book[shape] = None
        add_shape(c_space, shape._shape)


def remove_shapes(space: pymunk.Space, shapes) -> None:
    """:func:`space_remove` for shapes alone, not kept in pymunk's ``_removed_shapes`` (which only its
    own step, never called here, empties)."""
    c_space, book, set_ = space._space, space._shapes, object.__setattr__
    for shape in shapes:
        set_(shape, "_space", _dead_ref)
        remove_shape(c_space, shape._shape)
        del book[shape]


class BatchBuffer(pymunk.batch.Buffer):
    """``pymunk.batch.Buffer`` that frees its C arrays when collected (pymunk 7.3's never does: a new
    one per reset leaked 0.5 KiB each)."""

    def __del__(self, _free_floats=_batch.lib.pmFloatArrayFree, _free_ints=_batch.lib.pmIntArrayFree):
        # the functions are bound here: at interpreter exit the module's globals may be gone
        _free_floats(self._float_arr)
        _free_ints(self._int_arr)


# -- Chipmunk called from compiled code (``world.step_kernel``): one compiled call a step, not four
# Python calls. The functions' addresses travel as integers (``address_of``) and are called through
# the pointer at run time, so the compiled code holds no address of this process and caches.
def address_of(cdata) -> int:
    """A cffi pointer's (or ``lib`` function's) address as a Python int."""
    return int(ffi.cast("uintptr_t", cdata))


def function_address(name: str) -> int:
    """The address of Chipmunk's (or pymunk's batch) C function ``name``."""
    return address_of(ffi.addressof(_batch.lib, name))


@intrinsic
def as_pointer(typingctx, address):
    """An int64 address as a ``void *`` (for ``numba.carray``)."""

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], ir.IntType(8).as_pointer())

    return types.voidptr(types.int64), codegen


@intrinsic
def call_step(typingctx, function, space, dt):
    """``cpSpaceStep(space, dt)`` through the function's address (``void (*)(cpSpace *, cpFloat)``)."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [pointer_t, ir.DoubleType()])
        builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(args[1], pointer_t), args[2]])
        return context.get_dummy_value()

    return types.none(types.int64, types.int64, types.float64), codegen


@intrinsic
def call_set_vect(typingctx, function, body, x, y):
    """``function(body, cpv(x, y))`` through the function's address (``void (*)(cpBody *, cpVect)``:
    ``cpBodySetPosition``, ``cpBodySetVelocity``; a cpVect by value travels as two doubles)."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [pointer_t, ir.DoubleType(), ir.DoubleType()])
        builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(args[1], pointer_t), args[2], args[3]])
        return context.get_dummy_value()

    return types.none(types.int64, types.int64, types.float64, types.float64), codegen


@intrinsic
def call_get_vect(typingctx, function, body):
    """``function(body)`` through the function's address (``cpVect (*)(const cpBody *)``:
    ``cpBodyGetPosition``, ``cpBodyGetVelocity``), as ``(x, y)``."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.LiteralStructType([ir.DoubleType(), ir.DoubleType()]), [pointer_t])
        vect = builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(args[1], pointer_t)])
        return context.make_tuple(builder, signature.return_type, [builder.extract_value(vect, 0), builder.extract_value(vect, 1)])

    return types.UniTuple(types.float64, 2)(types.int64, types.int64), codegen


@intrinsic
def call_space_shape(typingctx, function, space, shape):
    """``cpSpaceAddShape(space, shape)`` or ``cpSpaceRemoveShape(space, shape)`` through the function's address
    (both ``(cpSpace *, cpShape *)``; the add's returned shape is not read)."""

    def codegen(context, builder, signature, args):
        pointer_t = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [pointer_t, pointer_t])
        builder.call(builder.inttoptr(args[0], fnty.as_pointer()), [builder.inttoptr(a, pointer_t) for a in args[1:]])
        return context.get_dummy_value()

    return types.none(types.int64, types.int64, types.int64), codegen


@numba.njit(cache=True)
def each_shape(function, space, shapes):
    """``function(space, shape)`` for every ``cpShape *`` address of ``shapes`` in order: a lent space's
    obstacles removed and added back (:mod:`pathplan_env.world.space`) in one compiled call, Chipmunk's
    own calls in the order pymunk's loop made them (the Python loop cost a corridor crowd's reset ~30 µs)."""
    for k in range(shapes.shape[0]):
        call_space_shape(function, space, shapes[k])
