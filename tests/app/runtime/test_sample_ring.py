"""Every step's F_ext in shared memory (app/runtime/sample_ring.py): a reader gets every sample
once, oldest first; one that fell more than the ring behind is told how many it lost, and is never
handed a torn or overwritten sample; the writer may be a forked process, and it wakes an event loop
that waits for its next sample (and nobody when nobody waits)."""

import asyncio
import multiprocessing
import select
import time

import numpy as np

from app.runtime.sample_ring import SampleRing


def _wrench(i: int) -> np.ndarray:
    return np.arange(6.0) + 10.0 * i


def test_a_reader_gets_every_sample_once_in_order():
    ring = SampleRing(capacity=8)
    seen = 0
    got = []
    for i in range(20):
        ring.append(i * 1e-3, _wrench(i))
        if i % 3 == 0:
            rows, seen, lost = ring.since(seen)
            assert lost == 0
            got += list(rows)
    rows, seen, lost = ring.since(seen)
    got += list(rows)
    assert seen == 20
    assert lost == 0
    assert np.array_equal(np.array(got)[:, 0], np.arange(20) * 1e-3)
    assert np.array_equal(np.array(got)[:, 1:], np.array([_wrench(i) for i in range(20)]))


def test_a_reader_that_fell_behind_is_told_what_it_lost():
    ring = SampleRing(capacity=8)
    for i in range(30):
        ring.append(i * 1e-3, _wrench(i))
    rows, seen, lost = ring.since(0)
    # the oldest slot still whole is sample 23 (sample 22's slot is the next the writer fills)
    assert seen == 30
    assert lost == 23
    assert len(rows) == 7
    assert np.array_equal(rows[:, 0], np.arange(23, 30) * 1e-3)


def _write(ring: SampleRing, n: int) -> None:
    for i in range(n):
        ring.append(i * 1e-3, _wrench(i))


def test_the_writer_may_be_a_forked_process():
    ring = SampleRing(capacity=4096)
    child = multiprocessing.get_context("fork").Process(target=_write, args=(ring, 3000))
    child.start()
    seen, got, lost_total = 0, [], 0
    deadline = time.monotonic() + 120  # a bound for a hung writer, not a speed requirement
    while (child.is_alive() or seen < 3000) and time.monotonic() < deadline:
        rows, seen, lost = ring.since(seen)
        lost_total += lost
        got += list(rows)
    child.join()
    assert lost_total == 0
    assert len(got) == 3000
    assert np.array_equal(np.array(got)[:, 1:], np.array([_wrench(i) for i in range(3000)]))


def _readable(fd: int) -> bool:
    return bool(select.select([fd], [], [], 0)[0])


def test_a_waiting_event_loop_is_woken_by_each_sample_a_forked_writer_appends():
    ring = SampleRing(capacity=8)

    async def check() -> None:
        with ring.new_samples() as new_samples:
            for k in range(3):
                waiting = asyncio.ensure_future(new_samples.next())
                for _ in range(20):  # the loop turns: no sample, no wake-up
                    await asyncio.sleep(0)
                assert not waiting.done()
                child = multiprocessing.get_context("fork").Process(target=_write, args=(ring, 1))
                child.start()
                await asyncio.wait_for(waiting, 60)  # a bound for a starved machine, not a speed figure
                child.join()
                assert ring.count == k + 1

    asyncio.run(check())


def test_nobody_waiting_means_no_signal():
    ring = SampleRing(capacity=8)
    ring.append(0.0, _wrench(0))
    assert not _readable(ring.wake_fd)

    async def hold_then_leave() -> None:
        with ring.new_samples():
            pass

    asyncio.run(hold_then_leave())
    ring.append(0.001, _wrench(1))
    assert not _readable(ring.wake_fd)
