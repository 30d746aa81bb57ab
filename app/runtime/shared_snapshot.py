"""The latest snapshot in shared memory: the simulation process writes it after every step, the
server process reads it, with no pickling and no lock between them.

Layout (one anonymous shared mapping, made before the fork): a sequence counter (uint64), then the
numbers of the record as float64, then one fixed slot per text field. The writer is alone (a
seqlock): it makes the counter odd, writes, makes it even again; a reader copies the record and
retries when the counter was odd or changed meanwhile. The writer scatters all the numbers in one
go and skips a text it wrote last time (the same object), unless another writer wrote since.

The record is a tree of dataclasses whose leaves are numpy arrays (fixed shapes), numbers, bools
and texts (`str` or None), as the sample it is built from; a text longer than its slot is cut.
"""

from __future__ import annotations

import dataclasses
import mmap
import operator
import struct
from collections.abc import Callable
from typing import TYPE_CHECKING, Generic, TypeVar, cast

import numpy as np

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

TEXT_SLOT = 2048  # bytes per text field (2-byte length + UTF-8)
_NONE = 0xFFFF
_HEADER = 8  # the sequence counter
R = TypeVar("R", bound="DataclassInstance")  # the record's type


@dataclasses.dataclass(frozen=True)
class _Node:
    """How to rebuild one dataclass of the record: its type and, per field, a leaf or a node."""

    cls: type
    fields: tuple[tuple[str, _Leaf | _Node], ...]  # (name, a leaf or a node)


@dataclasses.dataclass(frozen=True)
class _Leaf:
    kind: str  # "array", "float", "int", "bool" or "text"
    start: int  # float index (numbers) or byte offset (texts)
    shape: tuple[int, ...] = ()
    size: int = 1  # elements of an array (the product of its shape, counted once here, not per read)


class SharedSnapshot(Generic[R]):
    """A seqlock-protected copy of a record (a dataclass tree) in memory shared across a fork."""

    def __init__(self, sample: R) -> None:
        self._arrays: list[tuple[Callable, int, int]] = []  # (getter, start, stop) in floats
        self._numbers: list[tuple[Callable, int]] = []
        self._texts: list[tuple[Callable, int]] = []  # (getter, byte offset)
        self._floats = 0
        text_fields: list[tuple[Callable, int]] = []
        self._root = self._plan(sample, "", text_fields)
        numbers_bytes = 8 * self._floats
        for getter, index in text_fields:
            self._texts.append((getter, _HEADER + numbers_bytes + index * TEXT_SLOT))
        self._size = _HEADER + numbers_bytes + len(text_fields) * TEXT_SLOT
        self._memory = mmap.mmap(-1, self._size)  # MAP_SHARED | MAP_ANONYMOUS: shared with the fork
        self._numbers_view = np.frombuffer(self._memory, np.float64, self._floats, _HEADER)
        # where the writer puts its values: every array's elements, then the numbers (one scatter)
        self._index = np.concatenate(
            [np.arange(start, stop) for _, start, stop in self._arrays]
            + [np.array([i for _, i in self._numbers], dtype=np.intp)]
        ).astype(np.intp)
        self._array_getters = [g for g, _, _ in self._arrays]
        self._number_getters = [g for g, _ in self._numbers]
        self._written_texts: tuple[int, list] = (-1, [])  # (the counter after this copy's last write, its texts)
        self._text_base = _HEADER + numbers_bytes
        self._seen = -1
        self._cached: R | None = None

    def _plan(self, obj: DataclassInstance, prefix: str, text_fields: list) -> _Node:
        fields: list[tuple[str, _Node | _Leaf]] = []
        for f in dataclasses.fields(obj):
            value, path = getattr(obj, f.name), prefix + f.name
            getter = operator.attrgetter(path)
            if dataclasses.is_dataclass(value) and not isinstance(value, type):
                fields.append((f.name, self._plan(value, path + ".", text_fields)))
            elif isinstance(value, np.ndarray):
                fields.append((f.name, _Leaf("array", self._floats, value.shape, value.size)))
                self._arrays.append((getter, self._floats, self._floats + value.size))
                self._floats += value.size
            elif isinstance(value, (bool, int, float)):
                kind = "bool" if isinstance(value, bool) else "int" if isinstance(value, int) else "float"
                fields.append((f.name, _Leaf(kind, self._floats)))
                self._numbers.append((getter, self._floats))
                self._floats += 1
            elif value is None or isinstance(value, str):
                fields.append((f.name, _Leaf("text", len(text_fields))))
                text_fields.append((getter, len(text_fields)))
            else:
                raise TypeError(f"{path}: cannot share a {type(value).__name__}")
        return _Node(type(obj), tuple(fields))

    # --- the writer (one process, one thread) -----------------------------------------------
    def write(self, record: R) -> None:
        memory = self._memory
        values = [getter(record).ravel() for getter in self._array_getters]
        values.append(np.array([getter(record) for getter in self._number_getters], dtype=np.float64))
        flat = np.concatenate(values)
        (seq,) = struct.unpack_from("<Q", memory, 0)
        mine, written = self._written_texts
        if seq != mine:  # another writer (e.g. a restarted simulation's) wrote since: rewrite every text
            written = [object()] * len(self._texts)
        self._written_texts = (seq + 2, written)
        struct.pack_into("<Q", memory, 0, seq + 1)  # odd: being written
        self._numbers_view[self._index] = flat
        for k, (getter, offset) in enumerate(self._texts):
            text = getter(record)
            if text is written[k]:  # unchanged (the same str object, or None): already there
                continue
            written[k] = text
            if text is None:
                struct.pack_into("<H", memory, offset, _NONE)
            else:
                data = text.encode("utf-8", "replace")[: TEXT_SLOT - 2]
                struct.pack_into("<H", memory, offset, len(data))
                memory[offset + 2 : offset + 2 + len(data)] = data
        struct.pack_into("<Q", memory, 0, seq + 2)  # even: complete

    # --- readers (any thread of the other process) ------------------------------------------
    def read(self) -> R:
        """The latest complete record (the same object again while nothing new was written)."""
        while True:
            (before,) = struct.unpack_from("<Q", self._memory, 0)
            if before == self._seen:
                return cast(R, self._cached)  # set with _seen
            if before % 2:
                continue  # being written (a few microseconds)
            data = self._memory[: self._size]  # a copy
            (after,) = struct.unpack_from("<Q", self._memory, 0)
            if after == before:
                break
        numbers = np.frombuffer(data, np.float64, self._floats, _HEADER).copy()
        record = cast(R, self._build(self._root, numbers, data))  # the sample's tree, so an R
        self._seen, self._cached = before, record
        return record

    @property
    def written(self) -> int:
        """How many records were written so far."""
        return struct.unpack_from("<Q", self._memory, 0)[0] // 2

    def _build(self, node: _Node, numbers: np.ndarray, data: bytes) -> object:
        kwargs: dict[str, object] = {}
        for name, part in node.fields:
            if isinstance(part, _Node):
                kwargs[name] = self._build(part, numbers, data)
            elif part.kind == "array":
                kwargs[name] = numbers[part.start : part.start + part.size].reshape(part.shape)
            elif part.kind == "text":
                offset = self._text_base + part.start * TEXT_SLOT
                (length,) = struct.unpack_from("<H", data, offset)
                kwargs[name] = (
                    None if length == _NONE else data[offset + 2 : offset + 2 + length].decode("utf-8", "replace")
                )
            else:
                value = numbers[part.start]
                kwargs[name] = (
                    bool(value) if part.kind == "bool" else int(value) if part.kind == "int" else float(value)
                )
        return node.cls(**kwargs)
