"""What a wake-up costs between two processes taking turns (the sandbox's boundary without the
controller): a round trip parent -> child -> parent by each means, with both on one CPU (as the
sandbox keeps them) and, where there are two, on two CPUs; and with every core busy.

    .venv/bin/python -m bench.wakeup [--rounds 20000]

pipe: one byte each way (what sim/controllers/sandbox/wire.py uses); eventfd: one eventfd each
way; futex: a word in shared memory, FUTEX_WAIT/WAKE through ctypes; yield: spinning on a word in
shared memory with sched_yield (no blocking at all: it takes the CPU whenever the other side runs).
"""

from __future__ import annotations

import argparse
import ctypes
import mmap
import os
import subprocess
import sys
import time

import numpy as np

_LIBC = ctypes.CDLL(None, use_errno=True)
SYS_FUTEX, FUTEX_WAIT, FUTEX_WAKE = 202, 0, 1  # x86-64


def _pipe():
    to_child, to_parent = os.pipe(), os.pipe()
    return (
        lambda: (os.write(to_child[1], b"\1"), os.read(to_parent[0], 64)),
        lambda: (os.read(to_child[0], 64), os.write(to_parent[1], b"\1")),
    )


def _eventfd():
    to_child, to_parent = os.eventfd(0), os.eventfd(0)
    return (
        lambda: (os.eventfd_write(to_child, 1), os.eventfd_read(to_parent)),
        lambda: (os.eventfd_read(to_child), os.eventfd_write(to_parent, 1)),
    )


def _words():
    memory = mmap.mmap(-1, 4096)
    return ctypes.c_uint32.from_buffer(memory, 0), ctypes.c_uint32.from_buffer(memory, 64), memory


def _futex():
    request, answer, _memory = _words()

    def wait(word, old):
        while word.value == old:
            _LIBC.syscall(SYS_FUTEX, ctypes.byref(word), FUTEX_WAIT, old, None, None, 0)

    def wake(word, value):
        word.value = value
        _LIBC.syscall(SYS_FUTEX, ctypes.byref(word), FUTEX_WAKE, 1, None, None, 0)

    def parent():
        old = answer.value
        wake(request, request.value + 1)
        wait(answer, old)

    def child():
        wait(request, answer.value)
        wake(answer, request.value)

    return parent, child


def _yield():
    request, answer, _memory = _words()

    def parent():
        request.value += 1
        while answer.value != request.value:
            os.sched_yield()

    def child():
        while request.value == answer.value:
            os.sched_yield()
        answer.value = request.value

    return parent, child


MEANS = {"pipe": _pipe, "eventfd": _eventfd, "futex": _futex, "yield": _yield}


def round_trip(make, rounds: int, cpus: tuple[int, int] | None) -> tuple[float, float]:
    """(median wall s, CPU s of both processes) per round trip."""
    parent, child = make()
    pid = os.fork()
    if pid == 0:
        try:
            if cpus:
                os.sched_setaffinity(0, {cpus[1]})
            for _ in range(rounds):
                child()
        finally:
            os._exit(0)
    if cpus:
        os.sched_setaffinity(0, {cpus[0]})
    times = np.empty(rounds)
    before = os.times()
    for i in range(rounds):
        started = time.perf_counter()
        parent()
        times[i] = time.perf_counter() - started
    os.waitpid(pid, 0)
    after = os.times()
    cpu = sum(after[:4]) - sum(before[:4])
    os.sched_setaffinity(0, set(range(os.cpu_count() or 1)))
    return float(np.median(times)), cpu / rounds


def busy_cores(count: int) -> list[subprocess.Popen]:
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=20000)
    args = parser.parse_args()
    cpus = sorted(os.sched_getaffinity(0))
    placements = {"one CPU": (cpus[0], cpus[0])} | ({"two CPUs": (cpus[0], cpus[1])} if len(cpus) > 1 else {})
    for load in ("idle", "busy"):
        hogs = busy_cores(len(cpus)) if load == "busy" else []
        try:
            for where, pair in placements.items():
                for name, make in MEANS.items():
                    if load == "busy" and name == "yield" and where == "two CPUs":
                        continue  # each side spins against a busy loop: seconds per round
                    wall, cpu = round_trip(make, args.rounds if load == "idle" else args.rounds // 10, pair)
                    print(
                        f"{load:4} {where:8} {name:8} round trip median {wall * 1e6:6.1f} us, CPU {cpu * 1e6:6.1f} us"
                    )
        finally:
            for hog in hogs:
                hog.kill()
                hog.wait()
    with open("/proc/loadavg") as handle:
        print(f"load average while measuring: {handle.read().split()[0]} ({len(cpus)} cores)")


if __name__ == "__main__":
    main()
