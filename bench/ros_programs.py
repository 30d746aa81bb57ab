"""Students' ROS programs under `hri-lab run` (issue 27's figures), against a lab started here
(`hri-lab serve --exercises --view none`):

1. a service provided by a rospy program (tests/ros_programs/add_two_ints_server_rospy.py), called
   over HTTP one call at a time: p50/p99 of the round trip (ms);
2. /franka_state_controller/F_ext (the lab samples it at 1 kHz of simulation time) to a rospy
   subscriber with queue_size=1 (bench/ros_fext_subscriber.py): the share of the published
   messages that reached the callback, and of those that were dropped on the way (server queue,
   client queue);
3. a program's start-up time: from `hri-lab run` to its first request served (the lab answers
   404 "not provided yet" until the program has advertised the service).

    .venv/bin/python -m bench.ros_programs [--calls 1000] [--seconds 10]

Measure on a quiet machine: every figure here depends on the cores being free.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

import httpx

from app.cli.launch import running_server

ROOT = Path(__file__).resolve().parent.parent
SERVER = ROOT / "tests" / "ros_programs" / "add_two_ints_server_rospy.py"
SUBSCRIBER = Path(__file__).resolve().parent / "ros_fext_subscriber.py"


def hri_lab_run(url: str, program: Path, *args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "app.cli", "run", "--url", url, str(program), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        cwd=ROOT,
    )


def stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.send_signal(2)  # Ctrl+C
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def percentile(values: list[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(share * (len(ordered) - 1))))]


def startup_and_latency(url: str, calls: int) -> tuple[float, list[float]]:
    http = httpx.Client(base_url=url, timeout=30)
    started = time.perf_counter()
    program = hri_lab_run(url, SERVER)
    try:
        while http.post("/services/add_two_ints", json={"a": 1, "b": 2}).status_code != 200:
            if program.poll() is not None:
                raise RuntimeError("the program ended:\n" + program.stdout.read())
            time.sleep(0.005)
        first = time.perf_counter() - started
        for _ in range(20):  # warm-up
            http.post("/services/add_two_ints", json={"a": 1, "b": 2})
        latencies = []
        for i in range(calls):
            t0 = time.perf_counter()
            answer = http.post("/services/add_two_ints", json={"a": i, "b": 1})
            latencies.append((time.perf_counter() - t0) * 1e3)
            assert answer.json() == {"sum": i + 1}, answer.text
        return first, latencies
    finally:
        stop(program)


def fext(url: str, seconds: float) -> dict:
    program = hri_lab_run(url, SUBSCRIBER, str(seconds))
    out, _ = program.communicate(timeout=seconds + 120)
    line = next((x for x in out.splitlines() if x.startswith("{")), None)
    if line is None:
        raise RuntimeError("the subscriber printed no result:\n" + out)
    import json

    return json.loads(line)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=1000)
    parser.add_argument("--seconds", type=float, default=10.0, help="how long the F_ext subscriber listens")
    args = parser.parse_args(argv)
    with running_server("--view", "none", "--exercises") as lab:
        first, latencies = startup_and_latency(lab.url, args.calls)
        print(
            f"rospy service over HTTP ({args.calls} calls, one at a time): p50 {percentile(latencies, 0.5):.2f} ms, "
            f"p99 {percentile(latencies, 0.99):.2f} ms, mean {statistics.fmean(latencies):.2f} ms"
        )
        print(f"start-up: `hri-lab run` to the first request served: {first:.2f} s")
        figures = fext(lab.url, args.seconds)
        published = figures["published"]
        print(
            f"F_ext at 1 kHz to a rospy subscriber (queue_size=1), {args.seconds:g} s: {published} published, "
            f"{figures['arrived']} reached the program, {figures['handled']} the callback: "
            f"{100 * (1 - figures['handled'] / published):.1f} % dropped "
            f"({100 * (1 - figures['arrived'] / published):.1f} % before the program)"
        )


if __name__ == "__main__":
    main()
