"""Waiting in tests: for a condition (polls, never asserts on how long it took) and for a
student's node (tests/nodes/) to say it is ready."""

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

NODES = Path(__file__).parent / "nodes"


def wait_for(predicate, timeout: float = 30.0):
    """predicate()'s first truthy value; AssertionError when none came within `timeout` s (a bound
    for a hung test, not a speed requirement: keep it generous for a loaded machine)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("condition not met in time")


def wait_sim(snapshot, seconds: float, timeout: float = 60.0) -> None:
    """Until `seconds` of simulated time have passed (snapshot: a function giving the lab's latest
    snapshot): a wait measured in the simulation's own time, whatever the machine's load."""
    start = snapshot().time
    wait_for(lambda: snapshot().time >= start + seconds, timeout)


def process_gone(pid: int) -> bool:
    """True when process `pid` has ended: no such process, or a zombie (this test run is the
    subreaper of its descendants, tests/conftest.py, so an orphan that died is reaped here)."""
    try:
        with open(f"/proc/{pid}/stat") as handle:
            state = handle.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return True
    if state in ("Z", "X"):
        try:
            os.waitpid(pid, os.WNOHANG)
        except ChildProcessError:
            pass
        return True
    return False


def child_named(pid: int, name: str, other_than: int | None = None, timeout: float = 30.0) -> int:
    """The one child of process `pid` that calls itself `name` (its /proc/PID/comm: the server's
    "hri-lab-sim", "hri-lab-camera"), and not `other_than`. Waited for: a server prints that it is
    ready once it forked its children, which name themselves when they first run."""

    def named() -> list[int]:
        found = []
        for task in os.listdir(f"/proc/{pid}/task"):
            try:
                with open(f"/proc/{pid}/task/{task}/children") as handle:
                    children = [int(child) for child in handle.read().split()]
            except OSError:
                continue  # the thread ended meanwhile
            for child in children:
                try:
                    with open(f"/proc/{child}/comm") as handle:
                        if handle.read().strip() == name and child != other_than:
                            found.append(child)
                except OSError:
                    pass  # gone meanwhile
        return found

    (child,) = wait_for(lambda: len(found := named()) == 1 and found, timeout)
    return child


def start_node(lab, script: str, *args: str) -> subprocess.Popen:
    """tests/nodes/SCRIPT connected to the lab (a running_server), once it printed "node ready"."""
    node = subprocess.Popen(
        [sys.executable, str(NODES / script), "--port", str(lab.port), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    line = node.stdout.readline()
    assert line.startswith("node ready"), line + node.stdout.read()
    return node


def wait_provided(url: str, *services: str, timeout: float = 30.0) -> None:
    """Until the lab names a program's node, not its own, as each service's provider (`GET
    /services/NAME`, as `rosservice info`): roslibpy's advertise does not wait for the lab, so a
    roslibpy node's "ready" line can come before the lab has its services (the autograder's wait)."""
    from app.grading.gradescope import provided_by_nodes

    missing = provided_by_nodes(url, list(services), timeout)
    assert not missing, f"still the lab's own after {timeout} s: {missing}"


def stop_node(node: subprocess.Popen) -> None:
    node.terminate()
    node.wait(timeout=10)
    node.stdout.close()


def within(call, timeout: float = 30.0, what: str = "a call"):
    """call()'s value, called on a daemon thread; AssertionError when it has not returned within
    `timeout` s (for a blocking receive that has no timeout of its own: a regression fails the test
    instead of hanging it; the thread is left blocked until its socket closes)."""
    box: list = []
    errors: list = []

    def run():
        try:
            box.append(call())
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting test
            errors.append(exc)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(timeout)
    if errors:
        raise errors[0]
    if not box:
        raise AssertionError(f"{what}: no answer within {timeout} s")
    return box[0]


def wait_terminal(client, action, goal_id, timeout=30.0):
    """An action goal's view once it ended (succeeded, aborted, preempted, rejected), over HTTP."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        view = client.get(f"/actions/{action}/goals/{goal_id}", params={"wait": 1.0, "after": 0}).json()
        if view["status"] in ("succeeded", "aborted", "preempted", "rejected"):
            return view
    raise AssertionError("goal did not finish")
