"""3D view cost: server-side time of one scene update (robot meshes, plate, box, palm, arrows,
plot) and whether the 1 kHz loop keeps its rate while one viewer (headless Chromium,
bench/page_responsiveness.py's) watches.

    .venv/bin/python -m bench.view_cost [--seconds 10] [--light]
"""

from __future__ import annotations

import argparse
import statistics
import time

from sim.world import World

from app.lab.actions import ACTIONS
from app.lab.lab import Lab
from app.lab.services import SERVICES
from app.ros.actions import ActionServer
from app.view.view3d import LabView
from bench import percentile
from bench.page_responsiveness import CHROMIUM


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--light", action="store_true", help="collision meshes, no shadows")
    args = parser.parse_args()

    lab = Lab()
    lab.start()
    view = LabView(lab, ActionServer(ACTIONS, lab), SERVICES, port=0, light=args.light)
    view.start()
    lab.call(World.start_lifting, 10.0)  # a moving scene
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
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
        page.goto(view.url)
        time.sleep(3.0)  # the viewer loads the meshes
        view.frame_times.clear()
        ticks0, t0 = lab.runtime.health().stats.ticks, time.perf_counter()
        time.sleep(args.seconds)
        stats = lab.runtime.health().stats
        rate = (stats.ticks - ticks0) / (time.perf_counter() - t0)
        frames = list(view.frame_times)
        browser.close()
    view.stop()
    lab.stop()
    mode = "light" if args.light else "full"
    print(
        f"3D update ({mode} meshes), server side: median {statistics.median(frames) * 1e3:.2f} ms, "
        f"p99 {percentile(frames, 0.99) * 1e3:.2f} ms per frame, {len(frames) / args.seconds:.1f} frames/s"
    )
    print(
        f"1 kHz loop with one viewer connected: {rate:.0f} ticks/s, lateness p50 {stats.lateness_p50 * 1e3:.3f} ms, "
        f"p99 {stats.lateness_p99 * 1e3:.3f} ms, overruns {stats.overruns}"
    )


if __name__ == "__main__":
    main()
