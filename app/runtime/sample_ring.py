"""Every step's F_ext in shared memory: a ring the simulation process appends to after each step
and the server reads from, so a 1 kHz subscriber (a node's `/franka_state_controller/F_ext` with
throttle_rate 0) gets every sample, whenever the server's own thread gets the CPU, instead of the
newest snapshot at the moments it looks.

Layout (one anonymous shared mapping, made before the fork): the count of samples written so far
(uint64), then CAPACITY slots of (time, wrench[6]) as float64. The writer is alone: it fills slot
count % CAPACITY, then publishes count + 1. A reader copies the slots after the last count it saw
and reads the count again: slots the writer may have overwritten meanwhile (more than CAPACITY
behind) are dropped, never returned torn.
"""

from __future__ import annotations

import mmap

import numpy as np

CAPACITY = 4096  # samples: about 4 s at 1 kHz
_FIELDS = 7  # time (s), then the wrench (N, Nm)


class SampleRing:
    def __init__(self, capacity: int = CAPACITY) -> None:
        self.capacity = capacity
        self._memory = mmap.mmap(-1, 8 + 8 * _FIELDS * capacity)  # MAP_SHARED | MAP_ANONYMOUS
        self._count = np.frombuffer(self._memory, np.uint64, 1, 0)
        self._slots = np.frombuffer(self._memory, np.float64, _FIELDS * capacity, 8).reshape(capacity, _FIELDS)

    def append(self, time: float, wrench: np.ndarray) -> None:
        """The writer (one process): one sample after a step."""
        count = int(self._count[0])
        slot = self._slots[count % self.capacity]
        slot[0] = time
        slot[1:] = wrench
        self._count[0] = count + 1

    @property
    def count(self) -> int:
        return int(self._count[0])

    def since(self, seen: int) -> tuple[np.ndarray, int, int]:
        """(samples written after the first `seen`, oldest first, as rows [time, wrench[6]]; the new
        count to pass next time; how many were lost: overwritten before they were read)."""
        count = self.count
        first = max(seen, count - self.capacity + 1)  # the slot being written next may be torn
        indices = np.arange(first, count) % self.capacity
        rows = self._slots[indices].copy()
        safe_from = self.count - self.capacity + 1  # what the writer may have overwritten while we copied
        if safe_from > first:
            rows = rows[safe_from - first :]
            first = safe_from
        return rows, count, first - seen
