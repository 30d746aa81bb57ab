"""How this machine's CPU keeps its pace: a fixed pure-Python computation (~0.15 ms on a quiet
core) timed again and again, 1 ms apart, for SECONDS s, with nothing of the lab running. On the
2-core development VM it takes 13-18 times as long in windows of 0.1-0.3 s about every 1.5 s,
idle or not: the windows in which a 1 kHz pipeline of Python (the lab's server, a program's reader)
falls behind and then catches up in a burst (docs/ros-programs-client.md#measured).

The computation runs with real-time scheduling where the system allows it (SCHED_FIFO, as the
simulation loop), so a late wake-up of this process is not taken for a slow CPU: what is timed is
the computation alone.

    .venv/bin/python -m bench.machine_pauses [--seconds 15]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

SLOW = 4.0  # an iteration this many times the median is slow
SAME_WINDOW_S = 0.2  # slow iterations closer than this belong to one window


def computation() -> int:
    total = 0
    for i in range(2000):
        total += i * i
    return total


def measure(seconds: float) -> tuple[float, list[tuple[float, float]]]:
    """(the median computation time in s, [(start, duration) of every computation])."""
    timings = []
    end = time.perf_counter() + seconds
    while time.perf_counter() < end:
        started = time.perf_counter()
        computation()
        timings.append((started, time.perf_counter() - started))
        time.sleep(0.001)
    return statistics.median(d for _, d in timings), timings


def windows(median: float, timings: list[tuple[float, float]]) -> list[tuple[float, float, float]]:
    """(start, end, worst slow-down) of each window of slow computations."""
    found: list[list[float]] = []
    for started, duration in timings:
        if duration > SLOW * median:
            if found and started - found[-1][1] < SAME_WINDOW_S:
                found[-1][1] = started + duration
                found[-1][2] = max(found[-1][2], duration / median)
            else:
                found.append([started, started + duration, duration / median])
    return [(a, b, c) for a, b, c in found]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=15.0)
    args = parser.parse_args(argv)
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(20))
        scheduling = "SCHED_FIFO"
    except (OSError, AttributeError):
        scheduling = "normal scheduling (no real-time allowed)"
    median, timings = measure(args.seconds)
    found = windows(median, timings)
    print(f"{len(timings)} computations over {args.seconds:g} s ({scheduling}), median {median * 1e6:.0f} us")
    if not found:
        print(f"no computation took {SLOW:g} times the median")
        return
    lengths = [(b - a) * 1e3 for a, b, _ in found]
    gaps = [found[i + 1][0] - found[i][0] for i in range(len(found) - 1)]
    print(
        f"{len(found)} windows where it took over {SLOW:g} times the median: {min(lengths):.0f}-{max(lengths):.0f} ms "
        f"long, up to {max(c for _, _, c in found):.1f} times"
        + (f", one every {statistics.median(gaps):.2f} s (median)" if gaps else "")
    )


if __name__ == "__main__":
    main()
