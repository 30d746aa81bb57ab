"""The camera handout's image server (tests/ros_programs/image_subscriber_rclpy.py: an rclpy node
whose image callback takes more than 50 ms, cv2.waitKey(50), at the camera's 30 images/s) answers
its get_target_position over HTTP while it receives the images; against a lab started here
(`hri-lab serve --exercises --view none`):

1. the program's start-up: from `hri-lab run` to its first request served (the lab answers 404 until
   the program has advertised the service);
2. p50/p99 of `POST /services/get_target_position` (one call at a time, --calls of them) while the
   node streams, and how many images its callback took per second meanwhile; twice: each call as
   soon as the one before was answered, then calls on a fixed schedule of POLL_HZ, as a controller
   that asks for the target asks. Back to back, every call comes while an image callback has just
   begun (the one before was answered between two callbacks), and rclpy's executor takes a ready
   subscription before a ready service: a call waits for that callback and the next one. On a
   schedule, a call comes at any moment of a callback: it waits for the rest of it and the next.

    .venv/bin/python -m bench.ros_image_server [--calls 300]

Every figure here depends on the cores being free: say the machine's load with them.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import httpx

from app.serving.launch import running_server
from bench.ros_programs import hri_lab_run, percentile, stop

PROGRAM = Path(__file__).resolve().parent.parent / "tests" / "ros_programs" / "image_subscriber_rclpy.py"
FRAME_LINE = "Receiving video frame"
POLL_HZ = 5.0  # calls per second of the scheduled calls


def timed_calls(http: httpx.Client, count: int, every_s: float | None = None) -> tuple[list[float], int]:
    """`count` calls of get_target_position, one at a time: each as soon as the one before was answered
    (every_s None) or at its time on a schedule of every_s (later, if the one before was late); the
    round trips (ms) and how many failed."""
    latencies, failures = [], 0
    start = time.perf_counter()
    for k in range(count):
        if every_s is not None:
            time.sleep(max(0.0, start + k * every_s - time.perf_counter()))
        t = time.perf_counter()
        answer = http.post("/services/get_target_position", json={"get": True})
        latencies.append((time.perf_counter() - t) * 1e3)
        failures += answer.status_code != 200
    return latencies, failures


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=300)
    args = parser.parse_args(argv)
    with running_server("--view", "none", "--exercises") as lab:
        http = httpx.Client(base_url=lab.url, timeout=30)
        started = time.perf_counter()
        program = hri_lab_run(lab.url, PROGRAM)
        lines: list[str] = []
        try:
            import threading

            def read() -> None:
                for line in program.stdout:  # type: ignore[union-attr]
                    lines.append(line)

            threading.Thread(target=read, daemon=True).start()
            while http.post("/services/get_target_position", json={"get": True}).status_code != 200:
                if program.poll() is not None:
                    raise RuntimeError("the program ended:\n" + "".join(lines))
                time.sleep(0.005)
            first = time.perf_counter() - started
            while sum(FRAME_LINE in line for line in lines) < 30:  # the camera's start, then streaming
                time.sleep(0.05)
            runs = {}
            for every_s in (None, 1.0 / POLL_HZ):
                frames_before, t0 = sum(FRAME_LINE in line for line in lines), time.perf_counter()
                latencies, failures = timed_calls(http, args.calls, every_s)
                seconds = time.perf_counter() - t0
                frames = sum(FRAME_LINE in line for line in lines) - frames_before
                runs[every_s] = (latencies, failures, seconds, frames)
        finally:
            stop(program)
    print(f"start-up: `hri-lab run` to the image server's first request served: {first:.2f} s")
    for every_s, (latencies, failures, seconds, frames) in runs.items():
        how = "back to back" if every_s is None else f"at {POLL_HZ:g} Hz"
        print(
            f"get_target_position over HTTP while the node streams ({args.calls} calls, one at a time, {how}, "
            f"{seconds:.1f} s): p50 {percentile(latencies, 0.5):.1f} ms, p99 {percentile(latencies, 0.99):.1f} ms, "
            f"max {max(latencies):.1f} ms, mean {statistics.fmean(latencies):.1f} ms, {failures} failed; "
            f"the image callback ran {frames / seconds:.1f} times/s meanwhile"
        )


if __name__ == "__main__":
    main()
