"""A component's state kept in one float64 array that the compiled step (sim/compiled_step.py)
reads and writes in place; the component's Python attributes are views of it.

    class Box:
        position = Field(0, 3)           # box.position is state[0:3] (a view; assignment copies in)
        rotation = Field(3, 3, 3)        # state[3:12] as a 3x3 view
        steps = Scalar(12)               # a float read/written at state[12]
        released = Flag(13)              # a bool read/written at state[13] (0.0 / 1.0)

The owner keeps the array in `self.state` (allocated with `allocate(cls)`; a class whose `state`
means something else names its array's attribute in `state_attribute`), so the layout is written
once, in the class, and the compiled kernels index it with the same constants.
"""

from __future__ import annotations

import numpy as np


def _array(obj) -> np.ndarray:
    return getattr(obj, getattr(type(obj), "state_attribute", "state"))


class Field:
    """state[start : start + prod(shape)] viewed with `shape`; setting copies the value in."""

    def __init__(self, start: int, *shape: int) -> None:
        self.start, self.shape = start, shape
        self.stop = start + int(np.prod(shape))

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        return _array(obj)[self.start : self.stop].reshape(self.shape)

    def __set__(self, obj, value) -> None:
        _array(obj)[self.start : self.stop] = np.asarray(value, dtype=float).reshape(-1)


class Scalar:
    """A float at state[index]."""

    def __init__(self, index: int) -> None:
        self.start, self.stop = index, index + 1

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        return float(_array(obj)[self.start])

    def __set__(self, obj, value) -> None:
        _array(obj)[self.start] = value


class Flag(Scalar):
    """A bool at state[index] (0.0 or 1.0)."""

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        return bool(_array(obj)[self.start])

    def __set__(self, obj, value) -> None:
        _array(obj)[self.start] = 1.0 if value else 0.0


def size(cls) -> int:
    """The length of `cls`'s state array: one past the last field declared on it (or its bases)."""
    stops = [f.stop for klass in cls.__mro__ for f in vars(klass).values() if isinstance(f, (Field, Scalar))]
    return max(stops)


def allocate(cls) -> np.ndarray:
    return np.zeros(size(cls))
