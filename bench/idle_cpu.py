"""An idle lab: CPU of `hri-lab serve --view none` (the server and its simulation and camera
processes, each apart too) while nothing happens, as CPU seconds over wall seconds; then the same while a node commands the robot
(lifting started), when the loop is back at 1 ms granularity. `--view light` (or `full`): the lab
as `make run` and the hub start it, its 3D view served and nobody looking at it. `--page TAB`: the
dashboard open on that tab in Chromium (SwiftShader, as the browser tests run it), the browser's
CPU (with playwright's driver) beside the lab's.

    .venv/bin/python -m bench.idle_cpu [--seconds 10] [--view none|light|full] [--page services|topics|...]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import time
from collections.abc import Iterator

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
    return sum(by_process(pid).values())


def cpu_seconds_but(pid: int, left_out: int) -> float:
    """user + system CPU of pid's descendants but itself and left_out's tree, s: the browser this
    process started, beside the lab it started."""
    return cpu_seconds(pid) - cpu_seconds(left_out) - _own(pid)


def _own(pid: int) -> float:
    """user + system CPU of one process (its threads), s."""
    with open(f"/proc/{pid}/stat") as handle:
        fields = handle.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime, stime


def share_of_a_core(pid: int, seconds: float, browser: bool = False) -> tuple[float, float]:
    """The lab's (pid's tree) share of a core over `seconds`, and the browser's (0 without one)."""

    def both() -> tuple[float, float]:
        return cpu_seconds(pid), cpu_seconds_but(os.getpid(), pid) if browser else 0.0

    (lab, page), wall = both(), time.perf_counter()
    time.sleep(seconds)
    (lab_after, page_after), elapsed = both(), time.perf_counter() - wall
    return (lab_after - lab) / elapsed, (page_after - page) / elapsed


def by_process(pid: int) -> dict[str, float]:
    """CPU seconds of each process of pid's tree, by its name (the server's, "hri-lab-sim", "hri-lab-camera")."""
    found: dict[str, float] = {}
    for p in _tree(pid):
        try:
            with open(f"/proc/{p}/comm") as name:
                key = "server" if p == pid else name.read().strip()
            found[key] = found.get(key, 0.0) + _own(p)
        except OSError:
            pass
    return found


@contextlib.contextmanager
def dashboard(url: str, tab: str) -> Iterator[None]:
    """The dashboard open on `tab` in Chromium until the context ends."""
    from playwright.sync_api import sync_playwright

    from bench.page_responsiveness import ARGS, CHROMIUM

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1500, "height": 900})
        page.goto(url + "/")
        page.locator(f"nav button[data-tab={tab}]").click()
        yield
        browser.close()


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--view", choices=("none", "light", "full"), default="none", help="the 3D view, not opened")
    parser.add_argument("--page", metavar="TAB", help="the dashboard open on this tab (services, topics, ...)")
    args = parser.parse_args()
    print(f"hri-lab serve --view {args.view}" + (f", the dashboard open on its {args.page} tab" if args.page else ""))
    with (
        running_server("--view", args.view) as server,
        httpx.Client(base_url=server.url, timeout=10.0) as http,
        dashboard(server.url, args.page) if args.page else contextlib.nullcontext(),
    ):
        time.sleep(2.0)  # start-up work done (first requests, kernels warm, the page drawn)
        parts, wall = by_process(server.proc.pid), time.perf_counter()
        idle, page = share_of_a_core(server.proc.pid, args.seconds, bool(args.page))
        parts_after, elapsed = by_process(server.proc.pid), time.perf_counter() - wall
        health = http.get("/health").json()
        print(
            f"idle server: {idle * 100:.1f} % of a core ({args.seconds:g} s; loop rate "
            f"{health['rate_hz']:.0f} Hz, {health['batched_ticks']} of {health['ticks']} ticks stepped in idle batches)"
            + (f"; the browser {page * 100:.1f} %" if args.page else "")
        )
        print(
            "  by process: "
            + ", ".join(f"{k} {(v - parts.get(k, 0.0)) / elapsed * 100:.2f} %" for k, v in sorted(parts_after.items()))
        )
        http.post("/services/start_cooperative_lifting", json={"force": 10.0})
        time.sleep(1.0)
        busy, page = share_of_a_core(server.proc.pid, args.seconds, bool(args.page))
        health = http.get("/health").json()
        http.post("/services/stop_cooperative_lifting", json={})
        print(
            f"lifting running: {busy * 100:.1f} % of a core; loop lateness p50 {health['lateness_p50_ms']:.3f} ms, "
            f"p99 {health['lateness_p99_ms']:.3f} ms" + (f"; the browser {page * 100:.1f} %" if args.page else "")
        )
    print(f"load average: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
