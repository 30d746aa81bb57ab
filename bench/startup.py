"""Time from process start to a ready server, and its memory: the server process and the simulation
process it forks, each as resident (RSS), and together as proportional set size (PSS: the pages
they share since the fork counted once).

    .venv/bin/python -m bench.startup [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics

from app.serving.launch import ServerProcess


def _proc_mb(pid: int, file: str, key: str) -> float:
    """A `key: N kB` line of /proc/PID/FILE, in MB."""
    with open(f"/proc/{pid}/{file}") as lines:
        for line in lines:
            if line.startswith(key):
                return int(line.split()[1]) / 1024.0
    return 0.0


def rss_mb(pid: int) -> float:
    return _proc_mb(pid, "status", "VmRSS:")


def pss_mb(pid: int) -> float:
    return _proc_mb(pid, "smaps_rollup", "Pss:")


def children(pid: int) -> list[int]:
    with open(f"/proc/{pid}/task/{pid}/children") as listing:
        return [int(c) for c in listing.read().split()]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for view in ("none", "full"):
        ready, server_rss, sim_rss, total_pss = [], [], [], []
        for _ in range(args.repeats):
            server = ServerProcess("--view", view, "--view-port", "0")
            ready.append(server.ready_after)
            pids = [server.proc.pid, *children(server.proc.pid)]
            server_rss.append(rss_mb(pids[0]))
            sim_rss.append(sum(rss_mb(p) for p in pids[1:]))
            total_pss.append(sum(pss_mb(p) for p in pids))
            server.stop()
        print(
            f"--view {view}: ready after median {statistics.median(ready):.2f} s (runs {', '.join(f'{x:.2f}' for x in ready)}; "
            f"target < 3 s); memory median: server RSS {statistics.median(server_rss):.0f} MB, simulation process RSS "
            f"{statistics.median(sim_rss):.0f} MB, both together (PSS) {statistics.median(total_pss):.0f} MB (target < 400 MB)"
        )


if __name__ == "__main__":
    main()
