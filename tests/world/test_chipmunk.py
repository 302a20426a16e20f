"""The world's fast adds and removes (``world.chipmunk``) leave pymunk's space as its own ``add`` and
``remove`` would: the same bodies and shapes, stepped the same."""

from __future__ import annotations

import pymunk

from pathplan_env.world.chipmunk import add_shapes, remove_shapes, space_add, space_remove


def _disc(x: float, vx: float) -> tuple[pymunk.Body, pymunk.Circle]:
    body = pymunk.Body(1.0, pymunk.moment_for_circle(1.0, 0, 0.5))
    body.position, body.velocity = (x, 0.0), (vx, 0.0)
    shape = pymunk.Circle(body, 0.5)
    shape.elasticity = 1.0
    return body, shape


def _positions(space: pymunk.Space, steps: int = 20) -> list:
    for _ in range(steps):
        space.step(0.05)
    return [tuple(b.position) for b in space.bodies]


def test_space_add_is_pymunks_add():
    ours, theirs = pymunk.Space(), pymunk.Space()
    space_add(ours, [*_disc(0.0, 1.0), *_disc(2.0, -1.0)])
    theirs.add(*_disc(0.0, 1.0), *_disc(2.0, -1.0))
    assert len(ours.bodies) == len(theirs.bodies) == 2 and len(ours.shapes) == 2
    assert all(shape.space is ours for shape in ours.shapes)
    assert _positions(ours) == _positions(theirs)  # the two discs meet and bounce the same


def test_space_remove_and_shapes_alone_leave_the_space_as_pymunks():
    space = pymunk.Space()
    body, shape = _disc(0.0, 0.0)
    other = _disc(3.0, 0.0)
    space_add(space, [body, shape, *other])
    space_remove(space, [shape, body])
    assert list(space.bodies) == [other[0]] and list(space.shapes) == [other[1]] and body.space is None
    remove_shapes(space, [other[1]])
    assert list(space.shapes) == [] and other[1].space is None
    add_shapes(space, [other[1]])  # its body is still in the space
    assert list(space.shapes) == [other[1]] and other[1].space is space
    _positions(space, 2)  # and the space steps
