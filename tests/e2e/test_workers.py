"""Worker processes die with their parent however it dies: the server killed with SIGKILL during
/run_experiment or /compare_controllers, `hri-lab grade --jobs 2` stopped with SIGTERM. Nothing
survives and nothing new is left in /dev/shm."""

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from app.serving.launch import ServerProcess
from tests.http_client import http

CONTROLLER = Path(__file__).resolve().parents[1] / "controllers" / "reference_sp.py"


def descendants(pid: int) -> set[int]:
    found, todo = set(), [pid]
    while todo:
        parent = todo.pop()
        for task in os.listdir(f"/proc/{parent}/task") if os.path.exists(f"/proc/{parent}/task") else ():
            try:
                children = Path(f"/proc/{parent}/task/{task}/children").read_text().split()
            except OSError:
                continue
            for child in map(int, children):
                if child not in found:
                    found.add(child)
                    todo.append(child)
    return found


def alive(pid: int) -> bool:
    """Running (a zombie is reaped here: the test run is the subreaper of orphans)."""
    try:
        os.waitpid(pid, os.WNOHANG)
    except ChildProcessError:
        pass
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(") ")[1][0] != "Z"
    except (OSError, IndexError):
        return False


def workers(pid: int) -> set[int]:
    """The spawned worker processes among pid's descendants."""
    found = set()
    for child in descendants(pid):
        try:
            if b"spawn_main" in Path(f"/proc/{child}/cmdline").read_bytes():
                found.add(child)
        except OSError:
            pass
    return found


def wait_gone(pids: set[int], timeout: float = 20.0) -> set[int]:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        left = {p for p in pids if alive(p)}
        if not left:
            return left
        time.sleep(0.1)
    return left


def shm() -> set[str]:
    return set(os.listdir("/dev/shm"))


def in_use() -> set[str]:
    """/dev/shm entries some live process maps under their names (shared memory; not a named
    semaphore: glibc's sem_open maps a temporary file and then links the name to it)."""
    names = set()
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            maps = Path(f"/proc/{pid}/maps").read_text()
        except OSError:
            continue
        names.update(line.split("/dev/shm/", 1)[1].split()[0] for line in maps.splitlines() if "/dev/shm/" in line)
    return names


def left_in_shm(before: set[str], settle: float = 30.0) -> set[str]:
    """multiprocessing's semaphores and shared memory created since `before` that stay: what a
    killed family left behind. A name another live process holds (another test worker's pool; its
    semaphore's mapping does not show the name, see in_use) goes when that process ends; one left
    by a killed family never does. Waits up to `settle` s for the names there now to go."""
    left = {n for n in shm() - before - in_use() if n.startswith(("sem.mp", "psm_"))}
    deadline = time.monotonic() + settle
    while left and time.monotonic() < deadline:
        time.sleep(0.2)
        left &= shm() - in_use()
    return left


@pytest.mark.parametrize(
    ("action", "goal"),
    [("run_experiment", {"trials": 3, "participant": "calm"}), ("compare_controllers", {"participants": "calm"})],
)
def test_killing_the_server_leaves_no_worker(action, goal):
    before = shm()
    server = ServerProcess("--view", "none")
    try:
        goal_id = http.post(f"{server.url}/actions/{action}/goals", json=goal).json()["goal_id"]
        assert http.get(f"{server.url}/actions/{action}/goals/{goal_id}").json()["status"] == "active"
        deadline = time.monotonic() + 60
        while not workers(server.proc.pid) and time.monotonic() < deadline:  # the action's pool has a worker
            time.sleep(0.1)
        family = descendants(server.proc.pid)
        assert workers(server.proc.pid)
        assert len(family) >= 3
        server.proc.kill()
        server.proc.wait()
        assert wait_gone(family) == set()
        assert not left_in_shm(before)
    finally:
        server.stop()


def test_sigterm_to_grade_leaves_no_worker():
    before = shm()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "grade", str(CONTROLLER), "--jobs", "2", "--reference", "flag"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 120
        while len(descendants(proc.pid)) < 2 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.1)
        family = descendants(proc.pid)
        assert len(family) >= 2, "the trial workers did not start"
        proc.terminate()
        proc.wait(timeout=30)
        assert wait_gone(family) == set()
        assert not left_in_shm(before)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
