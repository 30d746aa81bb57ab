"""The camera's latest image in shared memory: the camera process writes it, the server reads it,
with no pickling and no lock between them (a seqlock, as app/runtime/shared_snapshot.py).

Layout (one anonymous shared mapping, made before the fork): the sequence counter (uint64, odd
while a frame is being written), then the frame's simulated time (s, the pose it shows), the wall
clock (time.time(), s) when that pose was read and how long the render took (s), as float64, then
height x width x 3 bytes of BGR.
"""

from __future__ import annotations

import mmap
import struct
from dataclasses import dataclass

import numpy as np

_HEADER = struct.Struct("<Qddd")


@dataclass(frozen=True)
class Frame:
    """One rendered image: BGR, uint8, (height, width, 3), row 0 at the top."""

    image: np.ndarray
    time: float  # s, simulated: the snapshot whose pose it shows (its header stamp)
    posed_at: float  # s, wall clock (time.time()) when that snapshot was read
    render_s: float  # s the render took
    number: int  # frames written so far (1 = the first)


class SharedFrame:
    def __init__(self, width: int, height: int) -> None:
        self.shape = (height, width, 3)
        self._bytes = width * height * 3
        self._memory = mmap.mmap(-1, _HEADER.size + self._bytes)  # MAP_SHARED | MAP_ANONYMOUS
        self._pixels = np.frombuffer(self._memory, np.uint8, self._bytes, _HEADER.size)

    def write(self, image: np.ndarray, time: float, posed_at: float, render_s: float) -> None:
        """Publish a frame (one writer: the camera process)."""
        (seq,) = struct.unpack_from("<Q", self._memory, 0)
        struct.pack_into("<Q", self._memory, 0, seq + 1)  # odd: being written
        self._pixels[:] = image.reshape(-1)
        _HEADER.pack_into(self._memory, 0, seq + 1, time, posed_at, render_s)
        struct.pack_into("<Q", self._memory, 0, seq + 2)  # even: complete

    @property
    def number(self) -> int:
        """How many frames were written so far (cheap: read it to see whether a new one came)."""
        return struct.unpack_from("<Q", self._memory, 0)[0] // 2

    def read(self) -> Frame | None:
        """The latest complete frame (a copy), None before the first."""
        while True:
            seq, time, posed_at, render_s = _HEADER.unpack_from(self._memory, 0)
            if seq == 0:
                return None
            if seq % 2:
                continue  # being written (a fraction of a millisecond)
            image = self._pixels.copy()
            if struct.unpack_from("<Q", self._memory, 0)[0] == seq:
                return Frame(image.reshape(self.shape), time, posed_at, render_s, seq // 2)
