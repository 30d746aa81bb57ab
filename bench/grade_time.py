"""The sandbox's cost: one controller step in-process vs across the sandbox boundary (bubblewrap,
a shared-memory slot, a wake-up byte each way), the CPU a sandboxed step costs with the cores idle and busy (the child is kept on its
parent's CPU: sim/controllers/sandbox/), a child's start-up (a file's first: its jail; each later
one: a fork of the jail's zygote), and the wall time and CPU of a whole `hri-lab grade` of the
reference SP file.

    .venv/bin/python -m bench.grade_time [--steps 20000] [--no-grade]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from sim.controllers.interface import LiftingParams, start_lifting
from sim.controllers.plugin import PluginFactory
from sim.controllers.sandbox import pool
from sim.controllers.sp import SPController

REFERENCE = str(Path(__file__).resolve().parent.parent / "tests" / "controllers" / "reference_sp.py")


def step_times(controller, steps: int) -> np.ndarray:
    params = LiftingParams()
    start_lifting(params, 10.0)
    wrench, transform = np.array([0.5, -0.3, 12.0, 0.05, 0.0, 0.0]), np.eye(4)
    times = np.empty(steps)
    for i in range(steps):
        started = time.perf_counter()
        controller.step(wrench, transform, params, 1e-3)
        times[i] = time.perf_counter() - started
    return times


def cpu_per_step(steps: int) -> float:
    """CPU (s) per sandboxed step, parent and child together."""
    sandboxed = PluginFactory(REFERENCE)()
    child, parent = sandboxed._cpu_time(), time.process_time()
    step_times(sandboxed, steps)
    used = time.process_time() - parent + sandboxed._cpu_time() - child
    sandboxed.close()
    return used / steps


def start_up(count: int = 5) -> tuple[float, float, float]:
    """(wall s of a file's first child: its jail and zygote started; median wall s, mean child CPU s
    of each later one: forked by the zygote, the file loaded): what a grade pays once per worker,
    and once per graded item (the child's CPU read from /proc just after the load)."""
    pool.close_all()
    started = time.perf_counter()
    PluginFactory(REFERENCE)().close()
    first = time.perf_counter() - started
    walls, cpus = [], []
    for _ in range(count):
        started = time.perf_counter()
        controller = PluginFactory(REFERENCE)()
        walls.append(time.perf_counter() - started)
        cpus.append(controller._cpu_time())
        controller.close()
    pool.close_all()
    return first, float(np.median(walls)), float(np.mean(cpus))


def busy_cores(count: int) -> list[subprocess.Popen]:
    """Processes that keep `count` cores busy (what the test suite or a batch grade does)."""
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]


def grade_once(flags: list[str]) -> tuple[float, float, str]:
    """(wall s, CPU s of the grade and the processes it reaped, its last line) of one grade."""
    cpu_before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    run = subprocess.run(
        # the reference SP is the lab's own (0 points by default): graded as a file, flagged
        [sys.executable, "-m", "app.cli", "grade", REFERENCE, "--jobs", "2", "--quiet", "--reference", "flag", *flags],
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - cpu_before.ru_utime - cpu_before.ru_stime
    said = run.stdout.strip().splitlines()[-1] if run.stdout.strip() else run.stderr[-300:]
    return wall, cpu, f"exit {run.returncode}, {said}"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--no-grade", action="store_true")
    args = parser.parse_args()
    for load in ("idle", "busy"):
        hogs = busy_cores(os.cpu_count() or 1) if load == "busy" else []
        try:
            inside = step_times(SPController(), args.steps)
            sandboxed = PluginFactory(REFERENCE)()
            across = step_times(sandboxed, args.steps)
            sandboxed.close()
            if load == "idle":  # the same, the pair left where the scheduler puts it: what pinning saves
                unpinned = PluginFactory(REFERENCE)()
                unpinned._follow_parent = lambda: None  # type: ignore[method-assign]
                unpinned.load()
                for pid in unpinned._tree():  # a forked child has its zygote's CPUs: every one here
                    os.sched_setaffinity(pid, os.sched_getaffinity(0))
                loose = step_times(unpinned, args.steps)
                unpinned.close()
        finally:
            for hog in hogs:
                hog.kill()
                hog.wait()
        cores = "cores idle" if load == "idle" else "every core busy"
        print(
            f"SP step in-process ({cores}):   median {np.median(inside) * 1e6:.0f} us, p99 {np.percentile(inside, 99) * 1e6:.0f} us"
        )
        print(
            f"SP step sandboxed ({cores}):    median {np.median(across) * 1e6:.0f} us, p99 {np.percentile(across, 99) * 1e6:.0f} us"
        )
        print(
            f"boundary per step ({cores}):    {(np.median(across) - np.median(inside)) * 1e6:.0f} us (median difference)"
        )
        if load == "idle":
            print(
                f"  not kept on one CPU (cores idle):  {(np.median(loose) - np.median(inside)) * 1e6:.0f} us (median difference)"
            )
    idle = cpu_per_step(args.steps)
    hogs = busy_cores(os.cpu_count() or 1)
    try:
        busy = cpu_per_step(args.steps)
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
    print(f"CPU per sandboxed step (parent + child): {idle * 1e6:.0f} us, {busy * 1e6:.0f} us with every core busy")
    first, wall, cpu = start_up()
    print(f"a file's first child (bwrap, Python, numpy: the jail's zygote, then a fork): {first:.2f} s wall")
    print(
        f"each later child (forked by the zygote, the file loaded): {wall * 1e3:.1f} ms wall, {cpu * 1e3:.1f} ms CPU in the child"
    )
    if not args.no_grade:
        for flags in ([], ["--unsandboxed"]):
            wall, cpu, said = grade_once(flags)
            print(f"hri-lab grade reference_sp.py {' '.join(['--jobs', '2', *flags])}: {wall:.1f} s wall, {said}")
            if flags:
                print(
                    f"  CPU of the grade and all its processes: {cpu:.1f} s = {cpu / 2:.1f} s wall on 2 idle cores at best"
                )
            else:
                print(
                    f"  CPU without the jails' (getrusage does not see the processes inside bubblewrap): {cpu:.1f} s; "
                    "--unsandboxed does the same work in plain child processes, all counted:"
                )
    with open("/proc/loadavg") as handle:
        print(f"load average while measuring: {handle.read().split()[0]} (2 cores)")


if __name__ == "__main__":
    main()
