"""sim/controllers/sandbox/cgroup.py: one group's caps hold the sum of its processes (forks do not get
their own budget): its processes and threads, its memory, its CPU; closing it ends every process in
it, a double-forked orphan too. Where this machine makes no group, the grader's statement names the
weaker limits instead (app/grading/wall_trial.py `limits_of`)."""

import subprocess
import sys

import pytest

from sim.controllers.sandbox.cgroup import MIB, GroupLimits, TrialGroup, cgroup_kind

from app.grading.wall_trial import PROGRAM_MEMORY_BYTES, limits_of
from tests.waiting import process_gone, wait_for

KIND, WHY = cgroup_kind()


@pytest.fixture
def group(request):
    """A group with the test's limits (indirect parameter), closed at the end."""
    # no group where the machine makes none: every report says so, which the tests then assert
    made = None if KIND is None else TrialGroup(f"test-{request.node.name[:20]}", request.param, KIND)
    yield made
    if made is not None:
        made.close()


def run_in(group: TrialGroup | None, code: str, **kwargs) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-c", code], preexec_fn=None if group is None else group.join, text=True, **kwargs
    )


def weaker(group) -> bool:
    """No group here: the statement names what holds a program instead, and the caps below cannot be shown."""
    if group is not None:
        return False
    said = limits_of(None, WHY)
    assert said.startswith(f"per process only (no cgroup: {WHY}): RLIMIT_AS {PROGRAM_MEMORY_BYTES / MIB:.0f} MiB")
    assert "no cap on their sum, their count or their CPU" in said
    return True


FORKS = """
import os, time
n = 0
for _ in range(40):
    try:
        if os.fork() == 0:
            time.sleep(60)
            os._exit(0)
    except OSError:
        break
    n += 1
print(n, flush=True)
time.sleep(60)  # the parent stays in the group with its children until the group is closed
"""


@pytest.mark.parametrize("group", [GroupLimits(256 * MIB, 8, 1.0)], indirect=True)
def test_the_process_cap_counts_every_fork(group):
    if weaker(group):
        return
    child = run_in(group, FORKS, stdout=subprocess.PIPE)
    started = int(child.stdout.readline())
    assert started < 8  # the parent and its children together
    assert any(h.startswith("process cap: ") for h in group.hit()), group.hit()
    pids = group.pids()
    assert child.pid in pids and len(pids) == started + 1
    group.close()
    assert all(process_gone(p) for p in pids)
    child.wait(timeout=10)


HOG = """
import os
children = []
for _ in range(3):
    pid = os.fork()
    if pid == 0:
        block = bytearray(b"1") * (60 << 20)
        print("held", flush=True)
        import time; time.sleep(60)
        os._exit(0)
    children.append(pid)
for pid in children:
    os.waitpid(pid, 0)
"""


@pytest.mark.parametrize("group", [GroupLimits(128 * MIB, 32, 1.0)], indirect=True)
def test_the_memory_cap_holds_the_sum_of_the_processes(group):
    """Three children of 60 MiB each, under a cap of 128 MiB for all: at least one is killed."""
    if weaker(group):
        return
    child = run_in(group, HOG, stdout=subprocess.PIPE)
    wait_for(lambda: any(h.startswith("memory cap: ") for h in group.hit()), timeout=60)
    assert group.memory_peak() <= 128 * MIB
    group.close()
    child.wait(timeout=10)


SPIN = "while True: pass"


@pytest.mark.parametrize("group", [GroupLimits(256 * MIB, 8, 0.02)], indirect=True)
def test_the_cpu_cap_throttles_the_group(group):
    """2 % of a CPU: a spinning process is held back within a few periods (the kernel's count)."""
    if weaker(group):
        return
    spinner = run_in(group, SPIN)
    try:
        stat = next(f / "cpu.stat" for f in group.folders if (f / "cpu.stat").exists())
        wait_for(lambda: int(dict(line.split() for line in stat.read_text().splitlines())["nr_throttled"]) > 0)
    finally:
        group.close()
        spinner.wait(timeout=10)


ORPHAN = """
import os, time
middle = os.fork()
if middle == 0:
    if os.fork() == 0:
        time.sleep(60)
        os._exit(0)
    os._exit(0)
os.waitpid(middle, 0)
print("orphaned", flush=True)
time.sleep(60)
"""


@pytest.mark.parametrize("group", [GroupLimits(256 * MIB, 16, 1.0)], indirect=True)
def test_closing_a_group_ends_every_process_in_it(group):
    if weaker(group):
        return
    child = run_in(group, ORPHAN, stdout=subprocess.PIPE)
    child.stdout.readline()
    wait_for(lambda: len(group.pids()) == 2)  # the parent and the orphan (its parent exited)
    left = group.pids()
    group.close()
    assert all(process_gone(p) for p in left)
    assert group.folders == []
    child.wait(timeout=10)
