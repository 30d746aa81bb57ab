"""The mobile world's speed (docs/performance.md, "The mobile world"): microseconds per scan (360
rays cast against the arena's walls and its obstacle, with the LDS-01's noise; the issue asks
<= 50 us) and per control step of the whole world (watchdog, base, a scan every 40th step, the
monitor), and the real-time factor of a headless world driving round its obstacle (asked: >= 100).

    .venv/bin/python -m bench.mobile_speed [--repeats 5] [--scans 2000] [--seconds 60]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from sim.mobile.lidar import scan
from sim.mobile.world import MobileWorld, seeded_config


def time_scans(world: MobileWorld, count: int) -> tuple[float, float]:
    """(wall s, CPU s) per scan: the compiled cast of all rays from the robot's pose (noise included)."""
    arena, lidar = world.config.arena, world.config.lidar
    normals = np.random.default_rng(0).standard_normal(lidar.rays)
    noise, out = lidar.noise_args(), np.empty(lidar.rays)
    x, y, yaw = (float(v) for v in world.pose)
    start, cpu = time.perf_counter(), time.thread_time()
    for _ in range(count):
        scan(arena.walls_xy, arena.obstacle_rows, x, y, yaw, normals, noise, out)
    return (time.perf_counter() - start) / count, (time.thread_time() - cpu) / count


def time_world(seed: int, seconds: float) -> tuple[float, float, float]:
    """(wall s per step, its real-time factor, the factor in CPU time) of a world whose base drives
    an arc round the obstacle."""
    world = MobileWorld(seeded_config(seed))
    steps = int(round(seconds / world.config.dt))
    start, cpu = time.perf_counter(), time.thread_time()
    for k in range(steps):
        if k % 20 == 0:  # a node's /cmd_vel at 10 Hz
            world.drive(0.15, 0.3)
        world.step()
    elapsed, cpu = time.perf_counter() - start, time.thread_time() - cpu
    return elapsed / steps, seconds / elapsed, seconds / cpu


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scans", type=int, default=2000)
    parser.add_argument("--seconds", type=float, default=60.0)
    args = parser.parse_args()
    scans, scans_cpu, steps, factors, factors_cpu = [], [], [], [], []
    for seed in range(args.repeats):
        world = MobileWorld(seeded_config(seed))
        time_scans(world, 10)  # compiled (or loaded) before timing
        wall, cpu = time_scans(world, args.scans)
        scans.append(wall)
        scans_cpu.append(cpu)
        per_step, factor, factor_cpu = time_world(seed, args.seconds)
        steps.append(per_step)
        factors.append(factor)
        factors_cpu.append(factor_cpu)
    load = os.getloadavg()
    print(
        f"scan (360 rays, noise; asked <= 50 us): CPU median {statistics.median(scans_cpu) * 1e6:.1f} us; "
        f"wall best {min(scans) * 1e6:.1f} us, median {statistics.median(scans) * 1e6:.1f} us\n"
        f"world ({1 / MobileWorld().config.dt:.0f} Hz steps; asked >= 100x real time): "
        f"CPU {statistics.median(factors_cpu):.0f}x; wall best {max(factors):.0f}x, median {statistics.median(factors):.0f}x "
        f"(a step {statistics.median(steps) * 1e6:.1f} us)\n"
        f"{args.repeats} worlds, {args.seconds:g} s simulated each; load average {load[0]:.2f} {load[1]:.2f} "
        f"{load[2]:.2f} on {os.cpu_count()} cores (shared with other developers' work)"
    )


if __name__ == "__main__":
    main()
