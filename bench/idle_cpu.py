"""An idle lab: CPU of `hri-lab serve --view none` (the server and its simulation process) while
nothing happens, as CPU seconds over wall seconds; then the same while a node commands the robot
(lifting started), when the loop is back at 1 ms granularity. `--view light` (or `full`): the lab
as `make run` and the hub start it, its 3D view served and nobody looking at it.

    .venv/bin/python -m bench.idle_cpu [--seconds 10] [--view none|light|full]
"""

from __future__ import annotations

import argparse
import os
import time

import httpx

from app.serving.launch import running_server

TICKS = os.sysconf("SC_CLK_TCK")


def _tree(pid: int) -> list[int]:
    """pid and its descendants (from /proc/PID/task/*/children)."""
    pids, todo = [], [pid]
    while todo:
        current = todo.pop()
        pids.append(current)
        try:
            for tid in os.listdir(f"/proc/{current}/task"):
                with open(f"/proc/{current}/task/{tid}/children") as handle:
                    todo += [int(p) for p in handle.read().split()]
        except OSError:
            pass
    return pids


def cpu_seconds(pid: int) -> float:
    """user + system CPU of the process tree, s."""
    total = 0
    for p in _tree(pid):
        try:
            with open(f"/proc/{p}/stat") as handle:
                fields = handle.read().rsplit(")", 1)[1].split()
            total += int(fields[11]) + int(fields[12])  # utime, stime
        except OSError:
            pass
    return total / TICKS


def share_of_a_core(pid: int, seconds: float) -> float:
    cpu, wall = cpu_seconds(pid), time.perf_counter()
    time.sleep(seconds)
    return (cpu_seconds(pid) - cpu) / (time.perf_counter() - wall)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--view", choices=("none", "light", "full"), default="none", help="the 3D view, not opened")
    args = parser.parse_args()
    print(f"hri-lab serve --view {args.view}")
    with running_server("--view", args.view) as server, httpx.Client(base_url=server.url, timeout=10.0) as http:
        time.sleep(2.0)  # start-up work done (first requests, kernels warm)
        idle = share_of_a_core(server.proc.pid, args.seconds)
        health = http.get("/health").json()
        print(
            f"idle server: {idle * 100:.1f} % of a core ({args.seconds:g} s; loop rate "
            f"{health['rate_hz']:.0f} Hz, {health['batched_ticks']} of {health['ticks']} ticks stepped in idle batches)"
        )
        http.post("/services/start_cooperative_lifting", json={"force": 10.0})
        time.sleep(1.0)
        busy = share_of_a_core(server.proc.pid, args.seconds)
        health = http.get("/health").json()
        http.post("/services/stop_cooperative_lifting", json={})
        print(
            f"lifting running: {busy * 100:.1f} % of a core; loop lateness p50 {health['lateness_p50_ms']:.3f} ms, "
            f"p99 {health['lateness_p99_ms']:.3f} ms"
        )
    print(f"load average: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
