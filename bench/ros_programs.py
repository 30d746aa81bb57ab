"""Students' ROS programs under `hri-lab run` (issue 27's figures), against a lab started here
(`hri-lab serve --exercises --view none`):

1. a service provided by a rospy program (tests/ros_programs/add_two_ints_server_rospy.py), called
   over HTTP one call at a time: p50/p99 of the round trip (ms);
2. /franka_state_controller/F_ext (the lab samples it at 1 kHz of simulation time) to a rospy
   subscriber with queue_size=1 (bench/ros_fext_subscriber.py): the share of the published
   messages that reached the callback, and of those that were dropped on the way (server queue,
   client queue); each run followed by what the same callback loses on this machine with no lab
   running (bench/rospy_floor.py: a paced 1 kHz stream over TCP into rospy's own receive rule),
   since both depend on how promptly the machine wakes a thread (each F_ext run has a lab of its own,
   so that the reference runs with none); with --fext-runs N, the medians;
3. a program's start-up time: from `hri-lab run` to its first request served (the lab answers
   404 "not provided yet" until the program has advertised the service); and what a program's
   `from hri_lab.srv import DivideInts` costs in a fresh interpreter, against the import of the
   lab's declarations that it took before the hri_lab files shipped (app/lab/interface_files.py);
4. the same service called by another rospy program (bench/ros_service_caller.py) through
   rospy.ServiceProxy, one call at a time: p50/p99 (ms);
5. F_ext to the same subscriber whose callback computes 2 ms, slower than the messages come: how
   many it handled, and how far behind the freshest the messages it handled were (p50/p99): the
   newest each time, not a backlog of stale ones.

    .venv/bin/python -m bench.ros_programs [--calls 1000] [--seconds 10] [--fext-runs 1]

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

from app.serving.launch import running_server
from bench import rospy_floor

ROOT = Path(__file__).resolve().parent.parent
SERVER = ROOT / "tests" / "ros_programs" / "add_two_ints_server_rospy.py"
SUBSCRIBER = Path(__file__).resolve().parent / "ros_fext_subscriber.py"
CALLER = Path(__file__).resolve().parent / "ros_service_caller.py"
# a fresh interpreter's import, timed inside it: a program's hri_lab import now, and what it took before
HRI_LAB_IMPORT = (
    "import time; t = time.perf_counter(); from rosclient import interfaces; interfaces.install([]); "
    "from hri_lab.srv import DivideInts; print(time.perf_counter() - t)"
)
DECLARATIONS_IMPORT = (
    "import time; t = time.perf_counter(); import app.lab.services, app.lab.actions; print(time.perf_counter() - t)"
)


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


def import_seconds(code: str, runs: int = 5) -> float:
    """The median of `runs` fresh interpreters' own timing of `code`."""
    times = [
        float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True).stdout)
        for _ in range(runs)
    ]
    return statistics.median(times)


def program_to_program(url: str, calls: int) -> list[float]:
    server = hri_lab_run(url, SERVER)
    try:
        out, _ = hri_lab_run(url, CALLER, str(calls)).communicate(timeout=calls + 120)
    finally:
        stop(server)
    line = next((x for x in out.splitlines() if x.startswith("{")), None)
    if line is None:
        raise RuntimeError("the caller printed no result:\n" + out)
    import json

    return list(json.loads(line)["latencies_ms"])


SLOW_WORK_S = 0.002  # s a slow callback computes per message (twice F_ext's period)


def fext(url: str, seconds: float, work_s: float | None = None) -> dict:
    program = hri_lab_run(url, SUBSCRIBER, str(seconds), *([] if work_s is None else [str(work_s)]))
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
    parser.add_argument("--fext-runs", type=int, default=1, help="F_ext runs, each followed by its reference")
    args = parser.parse_args(argv)
    with running_server("--view", "none", "--exercises") as lab:
        first, latencies = startup_and_latency(lab.url, args.calls)
        print(
            f"rospy service over HTTP ({args.calls} calls, one at a time): p50 {percentile(latencies, 0.5):.2f} ms, "
            f"p99 {percentile(latencies, 0.99):.2f} ms, mean {statistics.fmean(latencies):.2f} ms"
        )
        print(f"start-up: `hri-lab run` to the first request served: {first:.2f} s")
        print(
            f"a program's `from hri_lab.srv import DivideInts` (fresh interpreter, median of 5): "
            f"{import_seconds(HRI_LAB_IMPORT) * 1e3:.0f} ms; the lab's declarations it imported before the files "
            f"shipped: {import_seconds(DECLARATIONS_IMPORT) * 1e3:.0f} ms"
        )
        between = program_to_program(lab.url, args.calls)
        print(
            f"rospy service called by another rospy program ({args.calls} calls, one at a time): "
            f"p50 {percentile(between, 0.5):.2f} ms, p99 {percentile(between, 0.99):.2f} ms"
        )
    lab_dropped, floor_dropped = [], []
    for _ in range(args.fext_runs):  # the lab's figure, then the machine's own with no lab running, in turns
        with running_server("--view", "none", "--exercises") as lab:
            figures = fext(lab.url, args.seconds)
        published = figures["published"]
        lab_dropped.append(100 * (1 - figures["handled"] / published))
        print(
            f"F_ext at 1 kHz to a rospy subscriber (queue_size=1), {args.seconds:g} s: {published} published, "
            f"{figures['arrived']} reached the program, {figures['handled']} the callback: "
            f"{lab_dropped[-1]:.1f} % dropped ({100 * (1 - figures['arrived'] / published):.1f} % before the "
            f"program); {figures['slow']} callbacks took over 1 ms"
        )
        floor = rospy_floor.measure(args.seconds)
        floor_dropped.append(floor["dropped"])
        print(
            f"the same callback with no lab (bench/rospy_floor.py: a paced 1 kHz TCP stream into rospy's "
            f"receive rule; no lab running), {args.seconds:g} s: {floor['published']} published, "
            f"{floor['handled']} the callback: {floor['dropped']:.1f} % dropped; {floor['slow']} callbacks took "
            f"over 1 ms"
        )
    with running_server("--view", "none", "--exercises") as lab:
        slow = fext(lab.url, args.seconds, SLOW_WORK_S)
    print(
        f"F_ext to the same subscriber whose callback computes {SLOW_WORK_S * 1e3:g} ms (slower than the "
        f"messages), {args.seconds:g} s: {slow['handled']} handled of {slow['published']}; behind the freshest "
        f"by p50 {slow['behind_ms_p50']:.1f} ms, p99 {slow['behind_ms_p99']:.1f} ms"
    )
    if args.fext_runs > 1:
        print(
            f"F_ext dropped, median of {args.fext_runs} runs: {statistics.median(lab_dropped):.1f} % through the "
            f"lab, {statistics.median(floor_dropped):.1f} % with no lab"
        )


if __name__ == "__main__":
    main()
