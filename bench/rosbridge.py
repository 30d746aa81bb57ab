"""Student nodes over rosbridge, on a real server (`serve --exercises`) and real roslibpy nodes:

1. a service call HTTP -> lab -> node -> back: POST /services/add_two_ints answered by the
   services template's node (a separate process), sequential calls, p50 / p99;
2. F_ext to a node at 1 kHz (throttle_rate 0): messages received vs. simulation ticks, share dropped;
3. the 1 kHz loop's lateness (/health, last 5000 ticks) while that node streams.

    .venv/bin/python -m bench.rosbridge [--calls 1000] [--seconds 5]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import roslibpy

from app.serving.launch import running_server
from bench import percentile

TEMPLATE = Path(__file__).resolve().parents[1] / "app" / "cli" / "templates" / "services_node.py"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--calls", type=int, default=1000)
    parser.add_argument("--seconds", type=float, default=5.0)
    args = parser.parse_args()
    with running_server("--view", "none", "--exercises") as lab:
        node = subprocess.Popen(
            [sys.executable, str(TEMPLATE), "--port", str(lab.port)], stdout=subprocess.PIPE, text=True
        )
        try:
            assert node.stdout.readline().startswith("node ready")
            with httpx.Client(base_url=lab.url, timeout=10.0) as http:
                for _ in range(50):  # warm up
                    http.post("/services/add_two_ints", json={"a": 1, "b": 2})
                latencies = []
                for i in range(args.calls):
                    started = time.perf_counter()
                    response = http.post("/services/add_two_ints", json={"a": i, "b": 1})
                    latencies.append(time.perf_counter() - started)
                    assert response.json() == {"sum": i + 1}
        finally:
            node.terminate()
            node.wait(timeout=10)
        print(
            f"service call HTTP -> lab -> node -> back ({args.calls} sequential calls, add_two_ints): "
            f"p50 {percentile(latencies, 0.5) * 1e3:.2f} ms, p99 {percentile(latencies, 0.99) * 1e3:.2f} ms"
        )

        ros = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")
        ros.run()
        stamps: list[float] = []
        lock = threading.Lock()

        def on_message(message):
            stamp = message["header"]["stamp"]
            with lock:
                stamps.append(stamp["sec"] + stamp["nanosec"] * 1e-9)

        topic = roslibpy.Topic(ros, "/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", throttle_rate=0)
        topic.subscribe(on_message)
        time.sleep(1.0)  # settle
        with lock:
            stamps.clear()
        time.sleep(args.seconds)
        health = httpx.get(f"{lab.url}/health").json()
        with lock:
            received = sorted(set(stamps))
        topic.unsubscribe()
        ros.close()
        ros.terminate()
        ticks = round((received[-1] - received[0]) * 1000) + 1
        print(
            f"F_ext to a node at 1 kHz for {args.seconds:g} s: {len(received)} of {ticks} ticks received, "
            f"{100 * (1 - len(received) / ticks):.1f} % dropped"
        )
        print(
            f"1 kHz loop while the node streams: {health['rate_hz']:.0f} ticks/s, lateness p50 "
            f"{health['lateness_p50_ms']:.3f} ms, p99 {health['lateness_p99_ms']:.3f} ms"
        )
        print(f"(median of the call latencies: {statistics.median(latencies) * 1e3:.2f} ms)")


if __name__ == "__main__":
    main()
