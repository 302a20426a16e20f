"""The world's pymunk space: built for an episode, lent whole to the next episode's world where it
fits, and its bodies read and written in one batch call each.

Building a space (a new Chipmunk space, the arena's walls, the scene's statics, a body and a shape
per obstacle) was most of a reset; the next episode of the same env usually has the same arena,
statics and obstacle count, so its world takes the previous space over (:meth:`SpaceKeeper._lend_space`)
and Chipmunk runs the episode exactly as in a new one (tested against new spaces, digests unchanged).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pymunk
import pymunk.batch

from pathplan_env.geometry.walls import pymunk_segments
from pathplan_env.scenarios.scenario import Scenario
from pathplan_env.world.chipmunk import (
    READ_BODY,
    WRITE_BODY,
    BatchBuffer,
    add_shapes,  # noqa: F401 (0.1.0's `pathplan_env.world_space` offered it: kept importable)
    address_of,
    each_body,
    each_shape,
    ffi,
    function_address,
    get_stamp,
    remove_shapes,  # noqa: F401 (as add_shapes)
    set_mass,
    set_radius,
    set_shape_counter,
    set_slop,
    set_time_step,
    space_add,
    space_remove,
    space_step,
)

_STATE_FIELDS = pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.VELOCITY
_ADD_SHAPE, _REMOVE_SHAPE = function_address("cpSpaceAddShape"), function_address("cpSpaceRemoveShape")
#: A lent space is renewed before Chipmunk's 32-bit stamps (one a step, one an insertion) near a wrap.
STAMP_BUDGET = 2**31


class LentSpace(NamedTuple):
    """What a world lends the next one (:meth:`SpaceKeeper._lend_space`): its space and what it keeps of it."""

    space: pymunk.Space
    walls: tuple
    walls_bounds: tuple
    statics: tuple
    objects: list  # body, shape, body, shape, ...
    pointers: list  # the bodies' cpBody addresses (the compiled step's)
    moving: list
    buffer: BatchBuffer
    request: object  # the batch read's request struct
    state: np.ndarray  # the numpy view onto the buffer
    inserts: int  # an upper bound on the shapes inserted so far
    radii: list  # the obstacles' radii (their bodies' masses and shapes' radii as set)
    shape_addresses: np.ndarray  # (n,) int64: the obstacles' cpShape pointers, in order


def body_pointers(objects: list) -> list[int]:
    """The cpBody addresses of ``objects``' bodies (body, shape, body, shape, ...), for the compiled
    step (found once a space is built: a space lent on keeps them)."""
    return [address_of(body._body) for body in objects[0::2]]


class SpaceKeeper:
    """The pymunk half of :class:`pathplan_env.world.simulation.World` (its base class): ``space``, the walls,
    statics and obstacles in it, and the numpy view ``_pymunk_state`` onto the batch buffer."""

    def _build_space(self, scenario: Scenario, recycle: SpaceKeeper | None, moving: list[bool], min_radius: float) -> None:
        """A new pymunk space: the walls, the scene's statics and the obstacles (``recycle`` lends
        its walls, statics and moving bodies where they fit: creating them was most of a reset)."""
        self.space = pymunk.Space()
        # No overlap correction: Chipmunk's bias velocity pushes interpenetrating bodies apart farther
        # than their speed allows (up to 1.24x a step's displacement, in ~6 % of obstacle steps).
        # Without it every body moves exactly speed x dt a step (tested); the elastic impulses alone
        # separate overlapping pairs.
        self.space.collision_bias = 1.0
        self.space.collision_slop = 1e-4 * min_radius  # default 0.1 m is a fifth of a small obstacle
        walls = recycle._release_walls(scenario.bounds) if recycle is not None else None
        self._walls = walls if walls is not None else self._make_walls(scenario.bounds, thickness=max(scenario.arena_diagonal, 1.0))
        self._walls_bounds = scenario.bounds
        space_add(self.space, self._walls)
        self._statics = ()
        if self._has_statics:
            # (before the state view below is attached: a body added later would make the batch read
            # reallocate the array under the view)
            statics = recycle._release_statics(self.static_segments) if recycle is not None else None
            self._statics = statics if statics is not None else pymunk_segments(self.static_segments.tolist())
            space_add(self.space, self._statics)
        spare = recycle._release_moving_obstacles() if recycle is not None else []
        objects = []
        for r, dynamic in zip(self.radii.tolist(), moving):
            if dynamic and spare:
                body, shape = spare.pop()
                set_mass(body._body, r * r)  # Body.mass's own C call, without its Python property layers
                set_radius(shape._shape, r)  # Circle.unsafe_set_radius's own C call
            else:
                if dynamic:
                    body = pymunk.Body(mass=r * r, moment=math.inf)  # equal density; discs never spin
                else:
                    body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)  # a resting obstacle is immovable
                shape = pymunk.Circle(body, r)
                shape.elasticity = 1.0  # friction is 0 by default
            objects += (body, shape)
        self._objects, self._moving, self._shape_addresses = objects, moving, None
        self._pointers = body_pointers(objects)
        space_add(self.space, objects)
        self._inserts = len(self._walls) + len(self._statics) + len(objects)  # (an upper bound on the shapes inserted)
        self._buffer = BatchBuffer()
        self._attach_state_view()

    def _lend_space(self, scenario: Scenario, moving: list[bool]) -> LentSpace | None:
        """Empty this world and lend the next one its whole pymunk space, walls, statics and bodies
        kept in place, if they fit it: the same arena and statics, the same obstacles moving
        (``None`` otherwise: the next world builds its own). The world is unusable afterwards.

        Chipmunk then runs the next episode exactly as in a new space (tested against new spaces):
        the obstacles' shapes leave (their contacts and spatial-index leaves with them) and return
        with the shape ids a new space gives them; the bodies spend their bias velocity and wait at
        the origin with zero velocity (:meth:`_park_bodies`); the index's leaf table has the
        size a new one grows to for the same count (it never shrank: the count never changed);
        its stamps only compare with each other (all renewed past :data:`STAMP_BUDGET`).
        """
        space = self.space
        if (space is None or moving != self._moving or scenario.bounds != self._walls_bounds or not self._walls
                or not self._same_statics(scenario.static_segments) or get_stamp(space._space) + self._inserts > STAMP_BUDGET):  # fmt: skip
            return None
        shapes, c_space = self._objects[1::2], space._space
        addresses = getattr(self, "_shape_addresses", None)
        if addresses is None or len(addresses) != len(shapes):
            addresses = np.array([address_of(shape._shape) for shape in shapes], np.int64)
        # Chipmunk's removals alone: pymunk's books (each shape's space, the space's shapes) stay as they
        # were, which is what _take_space's additions would restore (the space is unusable in between)
        each_shape(_REMOVE_SHAPE, address_of(c_space), addresses)
        self._park_bodies()
        set_time_step(c_space, 0.0)  # a new space's: no previous step to scale cached impulses by
        set_shape_counter(c_space, len(self._walls) - 1 + max(len(self._statics) - 1, 0))  # the ids after the static shapes'
        lent = LentSpace(space, self._walls, self._walls_bounds, self._statics, self._objects, self._pointers, self._moving, self._buffer,
                         self._request, self._pymunk_state, self._inserts + len(shapes), self.radii.tolist(), addresses)  # fmt: skip
        self.space, self._objects, self._moving, self._walls, self._statics = None, [], [], (), ()
        self._ints = self._address = None  # the compiled step's raw handles: this world steps no more (step_kernel)
        return lent

    def _take_space(self, lent: LentSpace, min_radius: float) -> None:
        """The previous world's space (:meth:`_lend_space`): this episode's radii and masses, the
        obstacles' shapes added back in order."""
        self.space, self._walls, self._walls_bounds, self._statics = lent.space, lent.walls, lent.walls_bounds, lent.statics
        self._objects, self._pointers, self._moving, self._buffer, self._request = lent.objects, lent.pointers, lent.moving, lent.buffer, lent.request
        self._pymunk_state, self._inserts = lent.state, lent.inserts
        c_space, objects = self.space._space, self._objects
        set_slop(c_space, 1e-4 * min_radius)  # (the collision bias stays 1.0: no overlap correction)
        radii = self.radii.tolist()
        if radii != lent.radii:  # (the same radii, set again, would write the same masses and mass infos: a crowd's are)
            for i, (r, dynamic) in enumerate(zip(radii, self._moving)):
                if dynamic:
                    set_mass(objects[2 * i]._body, r * r)
                set_radius(objects[2 * i + 1]._shape, r)
        self._shape_addresses = lent.shape_addresses
        each_shape(_ADD_SHAPE, address_of(c_space), lent.shape_addresses)  # (pymunk's books already list them: _lend_space)

    def _release_moving_obstacles(self) -> list:
        """Empty this world and hand over its moving obstacles' (body, shape) pairs for reuse.

        A body must leave exactly as a new one arrives, or the next episode would depend on history:
        - a contact leaves a bias velocity that Chipmunk spends in the next position update; a
          step without shapes spends it;
        - positions and velocities are zeroed (one batch write), so that the bodies enter the next
          space's spatial index at the origin as new bodies do (the index's structure decides the
          order of contacts, which decides the last bits of every bounce).
        """
        space_remove(self.space, self._objects[1::2])
        self._park_bodies()  # (the walls left already, or stay for the old space's end)
        space_remove(self.space, self._objects[0::2])
        pairs = [(self._objects[2 * i], self._objects[2 * i + 1]) for i, moving in enumerate(self._moving) if moving]
        self._objects, self._moving = [], []
        self._ints = self._address = None  # the compiled step's raw handles: this world steps no more (step_kernel)
        return pairs

    def _park_bodies(self) -> None:
        """After the obstacles' shapes left: a step without them spends the bodies' bias velocity, and
        the bodies wait at the origin, at rest, as new ones arrive."""
        space_step(self.space._space, 1e-9)
        self._pymunk_state[:] = 0.0
        self._write_bodies()

    def _same_statics(self, segments: np.ndarray) -> bool:
        """Whether ``segments`` are this world's static segments (both empty included)."""
        statics = self.static_segments
        if statics is segments:  # (a family's shared rows: wall_families._segments)
            return True
        return (statics.size == 0 and segments.size == 0) or (statics.shape == segments.shape and np.array_equal(statics, segments))

    # -- construction helpers ------------------------------------------------------------------
    def _make_walls(self, bounds, thickness: float) -> tuple:
        """Four thick static walls whose inner faces are the arena's edges (no tunnelling through them),
        on their own static body so that the next episode's world can take them over."""
        xmin, ymin, xmax, ymax = bounds
        h = thickness
        return pymunk_segments([
            (xmin - h, ymin - h, xmax + h, ymin - h, h),
            (xmin - h, ymax + h, xmax + h, ymax + h, h),
            (xmin - h, ymin - h, xmin - h, ymax + h, h),
            (xmax + h, ymin - h, xmax + h, ymax + h, h),
        ])  # fmt: skip

    def _release_walls(self, bounds) -> tuple | None:
        """Hand this world's walls to the next one if the arena is the same (building them was a
        sixth of a reset)."""
        if self._walls_bounds != tuple(bounds):
            return None
        space_remove(self.space, self._walls)
        walls, self._walls = self._walls, ()
        return walls

    def _release_statics(self, segments: np.ndarray) -> tuple | None:
        """Hand this world's wall and polygon segments to the next one if its geometry is the same
        (a family's episodes share it: building them was a tenth of a crowd family's reset). Chipmunk
        gives a shape a new id when it is added, so a recycled segment is a new one to the space."""
        if not self._statics or not self._same_statics(segments):
            return None
        space_remove(self.space, self._statics)
        statics, self._statics = self._statics, ()
        return statics

    def _attach_state_view(self) -> None:
        """Read the bodies once and keep a numpy view onto pymunk's batch array.

        Later reads of the same bodies refill that array in place (it never needs to grow), so the
        view stays valid. (``Buffer.set_float_buf`` would point pymunk at our own array instead, but
        pymunk 7.3 may reallocate it while reading.)

        The per-substep read calls the C iterator behind ``pymunk.batch.get_space_bodies`` with a
        request struct built once here: the wrapper's per-call set-up cost more than the read itself.
        """
        self._request = ffi.new("pmBatchedData *")
        self._request.fields = _STATE_FIELDS.value
        self._request.floatArray = self._buffer._float_arr
        self._request.intArray = self._buffer._int_arr
        self._read_bodies()
        array = self._buffer._float_arr
        raw = np.frombuffer(pymunk.batch.ffi.buffer(array.arr, 8 * array.num), dtype=np.float64)
        self._pymunk_state = raw[: 4 * self.n_obstacles].reshape(self.n_obstacles, 4)

    def _read_bodies(self) -> None:
        """``pymunk.batch.get_space_bodies`` into the view."""
        self._buffer._float_arr.num = 0  # Buffer.clear() for the float array, the only one we use
        each_body(self.space._space, READ_BODY, self._request)

    def _write_bodies(self) -> None:
        """``pymunk.batch.set_space_bodies`` from the view (it reads the array from its start)."""
        array = self._buffer._float_arr
        filled, array.num = array.num, 0
        each_body(self.space._space, WRITE_BODY, self._request)
        array.num = filled
