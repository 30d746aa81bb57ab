"""Real-time loop under load: tick lateness p50/p99 of the 1 kHz loop while `wrk` calls services
at a steady rate over loopback and one 3D client (headless Chromium, bench/page_responsiveness.py's;
light meshes) watches.

    .venv/bin/python -m bench.loop_latency [--rate 200] [--seconds 10] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import httpx

from app.serving.launch import free_port, running_server
from bench.page_responsiveness import CHROMIUM
from bench.service_latency import run_wrk


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rate", type=float, default=200.0)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    with running_server("--view", "light", "--view-port", str(free_port())) as server, sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=CHROMIUM,
            args=[
                "--no-sandbox",
                "--use-gl=swiftshader",
                "--enable-unsafe-swiftshader",
                "--disable-background-networking",
            ],
        )
        page = browser.new_page()
        page.goto(httpx.get(f"{server.url}/view").json()["url"])
        time.sleep(3.0)
        httpx.post(f"{server.url}/services/start_cooperative_lifting", json={"force": 10})
        rows = []
        for _ in range(args.repeats):
            before = httpx.get(f"{server.url}/health").json()
            run_wrk(server.url, args.rate, args.seconds, connections=20)
            after = httpx.get(f"{server.url}/health").json()  # lateness over the last 5000 ticks
            ticks = (after["ticks"] - before["ticks"]) / args.seconds
            rows.append(
                (after["lateness_p50_ms"], after["lateness_p99_ms"], ticks, after["overruns"] - before["overruns"])
            )
        browser.close()
    print(
        f"1 kHz loop with {args.rate:g} req/s of service calls and one 3D client ({args.repeats} x {args.seconds:g} s):"
    )
    print(
        f"  lateness p50 median {statistics.median(r[0] for r in rows):.3f} ms, "
        f"p99 median {statistics.median(r[1] for r in rows):.3f} ms (runs {', '.join(f'{r[1]:.2f}' for r in rows)}); target p99 < 1 ms"
    )
    print(f"  ticks/s median {statistics.median(r[2] for r in rows):.0f}; overruns {sum(r[3] for r in rows)}")


if __name__ == "__main__":
    main()
