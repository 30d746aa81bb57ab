"""The camera's figures: the renderer's rate (in this process, 640 x 480), and through a real
server: the rate of /image_raw at a node, the latency
from an image's stamp (the simulated time of its pose) to its arrival at a rospy node run with
`hri-lab run` (bench/ros_image_subscriber.py), and the 1 kHz loop's lateness without and with it.

The stamp is simulated time; it is put on the wall clock with the offset wall - sim_time read from
/health (the smallest of several reads: the loop runs in real time, so the offset holds).

    .venv/bin/python -m bench.camera [--seconds 10]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import httpx

from sim.camera_render import CameraRenderer, SceneSizes
from sim.world import World, WorldConfig

from app.serving.launch import running_server

NODE = Path(__file__).resolve().parent / "ros_image_subscriber.py"


def render_rate(frames: int = 60) -> tuple[float, float]:
    """(ms per image median, images per second) of the renderer alone."""
    world = World(WorldConfig())
    cfg = world.config
    renderer = CameraRenderer(
        SceneSizes((cfg.plate.width, cfg.plate.height, cfg.plate.offset), cfg.box.size, cfg.palm_size)
    )
    s = world.snapshot()
    renderer.render(s)
    times = []
    for _ in range(frames):
        started = time.perf_counter()
        renderer.render(s)
        times.append(time.perf_counter() - started)
    renderer.release()
    median = statistics.median(times)
    return median * 1e3, 1.0 / median


def sim_offset(url: str, reads: int = 20) -> float:
    """wall clock - simulated time (s): the smallest over `reads` reads of /health."""
    best = float("inf")
    for _ in range(reads):
        sim = httpx.get(f"{url}/health").json()["sim_time"]
        best = min(best, time.time() - sim)
    return best


def lateness(url: str, seconds: float) -> tuple[float, float]:
    time.sleep(seconds)  # the loop's figures cover its last 5000 ticks
    health = httpx.get(f"{url}/health").json()
    return health["lateness_p50_ms"], health["lateness_p99_ms"]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    ms, hz = render_rate()
    print(f"renderer alone (moderngl, EGL, llvmpipe), 640 x 480: {ms:.1f} ms per image median ({hz:.0f} images/s)")
    with running_server("--view", "none") as server:
        httpx.post(f"{server.url}/services/start_cooperative_lifting", json={"force": 10})
        idle = lateness(server.url, 6.0)
        node = subprocess.Popen(
            [sys.executable, "-m", "app.cli", "run", "--url", server.url, str(NODE), str(args.seconds)],
            stdout=subprocess.PIPE,
            text=True,
        )
        offset = sim_offset(server.url)
        watched = lateness(server.url, args.seconds * 0.8)  # while the node receives
        out, _ = node.communicate(timeout=args.seconds + 120)
        offset = min(offset, sim_offset(server.url))
    arrivals = json.loads(out.strip().splitlines()[-1])["arrivals"]
    latencies = sorted((arrived - (stamp + offset)) * 1e3 for arrived, stamp in arrivals)
    span = arrivals[-1][0] - arrivals[0][0]
    print(
        f"/image_raw at a rospy node (hri-lab run, cv_bridge) over {span:.1f} s: {(len(arrivals) - 1) / span:.1f} images/s"
    )
    print(
        f"  latency stamp -> arrival: median {statistics.median(latencies):.0f} ms, "
        f"p90 {latencies[int(0.9 * (len(latencies) - 1))]:.0f} ms"
    )
    print(
        f"1 kHz loop lateness (lifting on): no subscriber p50 {idle[0]:.3f} / p99 {idle[1]:.3f} ms; "
        f"with the /image_raw subscriber p50 {watched[0]:.3f} / p99 {watched[1]:.3f} ms"
    )


if __name__ == "__main__":
    main()
