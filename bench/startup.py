"""Time from process start to a ready server, and its resident memory.

    .venv/bin/python -m bench.startup [--repeats 3]
"""
from __future__ import annotations

import argparse
import statistics

from app.launch import ServerProcess


def rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for view in ("none", "full"):
        ready, memory = [], []
        for _ in range(args.repeats):
            server = ServerProcess("--view", view, "--view-port", "0")
            ready.append(server.ready_after)
            memory.append(rss_mb(server.proc.pid))
            server.stop()
        print(f"--view {view}: ready after median {statistics.median(ready):.2f} s (runs {', '.join(f'{x:.2f}' for x in ready)}; "
              f"target < 3 s), resident memory median {statistics.median(memory):.0f} MB (target < 400 MB)")


if __name__ == "__main__":
    main()
