"""Every step's F_ext in shared memory: a ring the simulation process appends to after each step
and the server reads from, so a 1 kHz subscriber (a node's `/franka_state_controller/F_ext` with
throttle_rate 0) gets every sample, whenever the server's own thread gets the CPU, instead of the
newest snapshot at the moments it looks.

Layout (one anonymous shared mapping, made before the fork): the count of samples written so far
(uint64), how many readers want to be woken (uint64), then CAPACITY slots of (time, wrench[6]) as
float64. The writer is alone: it fills slot count % CAPACITY, then publishes count + 1. A reader
copies the slots after the last count it saw and reads the count again: slots the writer may have
overwritten meanwhile (more than CAPACITY behind) are dropped, never returned torn.

Woken by the writer: while a reader watches (`watch`), the writer signals an eventfd after each
sample, so an event loop reads every sample as it is written (`NewSamples`), one at a time and 1 ms
apart as the steps are, as a 1 kHz ROS publisher sends. A reader that polls instead finds none or
two as often as one (its wake-ups drift against the steps') and sends pairs back to back, which a
subscriber with a queue of one, busy with the first, loses one of.
"""

from __future__ import annotations

import asyncio
import mmap
import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

CAPACITY = 4096  # samples: about 4 s at 1 kHz
_FIELDS = 7  # time (s), then the wrench (N, Nm)
_HEAD = 16  # bytes before the slots: the count, the watchers


class SampleRing:
    def __init__(self, capacity: int = CAPACITY) -> None:
        self.capacity = capacity
        self._memory = mmap.mmap(-1, _HEAD + 8 * _FIELDS * capacity)  # MAP_SHARED | MAP_ANONYMOUS
        self._count = np.frombuffer(self._memory, np.uint64, 1, 0)
        self._watchers = np.frombuffer(self._memory, np.uint64, 1, 8)
        self._slots = np.frombuffer(self._memory, np.float64, _FIELDS * capacity, _HEAD).reshape(capacity, _FIELDS)
        self.wake_fd = os.eventfd(0, os.EFD_NONBLOCK | os.EFD_CLOEXEC)  # inherited by the forked writer
        self._watch_lock = threading.Lock()
        self._new_samples: dict[asyncio.AbstractEventLoop, NewSamples] = {}

    def append(self, time: float, wrench: np.ndarray) -> None:
        """The writer (one process): one sample after a step; the watching readers woken."""
        count = int(self._count[0])
        slot = self._slots[count % self.capacity]
        slot[0] = time
        slot[1:] = wrench
        self._count[0] = count + 1
        if self._watchers[0]:
            try:
                os.eventfd_write(self.wake_fd, 1)
            except BlockingIOError:  # the counter is full: the readers are woken already
                pass

    def watch(self, readers: int) -> None:
        """`readers` more (or, negative, fewer) readers want the writer to signal `wake_fd` after
        each sample: it does while any does."""
        with self._watch_lock:
            self._watchers[0] = int(self._watchers[0]) + readers

    @contextmanager
    def new_samples(self) -> Iterator[NewSamples]:
        """The running event loop's waiter for the next sample, while the block runs."""
        loop = asyncio.get_running_loop()
        waiter = self._new_samples.get(loop)
        if waiter is None:
            waiter = self._new_samples[loop] = NewSamples(self, loop)
        try:
            with waiter.held():
                yield waiter
        finally:
            if not waiter.holders:  # the loop's last: forgotten with the loop
                self._new_samples.pop(loop, None)

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


class NewSamples:
    """The coroutines of one event loop that wait for the ring's next sample: the loop watches the
    writer's eventfd while at least one of them is held (`held`), and `next()` returns once a
    sample was written after the last wake-up."""

    def __init__(self, ring: SampleRing, loop: asyncio.AbstractEventLoop) -> None:
        self.ring, self.loop = ring, loop
        self._event = asyncio.Event()
        self.holders = 0

    @contextmanager
    def held(self) -> Iterator[None]:
        if self.holders == 0:
            self.ring.watch(1)
            self.loop.add_reader(self.ring.wake_fd, self._woken)
        self.holders += 1
        try:
            yield
        finally:
            self.holders -= 1
            if self.holders == 0:
                self.loop.remove_reader(self.ring.wake_fd)
                self.ring.watch(-1)

    def _woken(self) -> None:
        try:
            os.eventfd_read(self.ring.wake_fd)
        except BlockingIOError:  # read already (a wake-up of the same samples)
            return
        event, self._event = self._event, asyncio.Event()
        event.set()

    async def next(self) -> None:
        """Return once the writer has written a sample (since the last wake-up of this loop)."""
        await self._event.wait()
