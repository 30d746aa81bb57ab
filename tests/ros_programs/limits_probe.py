"""A hostile wall follower (graded by tests/e2e/test_grade_wall.py): instead of driving it tries to
take more than one submission's share, as the third attack pass's did, and prints what it got:
three forked children holding 700 MiB each at once (per-process limits let each have its own 2 GiB),
then as many sleeping processes as it can start (up to 300). Then it ends (its lines are quoted
in its report; the report says what the grader's limits caught)."""

import os
import select
import signal
import time

HOLD = 700 << 20
CHILDREN = 3
MOST_PROCESSES = 300


def hold(write_end, index):
    block = bytearray(b"\x01") * HOLD  # written, so every page is really held
    os.write(write_end, bytes([index]))
    time.sleep(120)
    return len(block)


gone = set()


def alive(pid):
    """Still running (a child found dead is reaped once and remembered)."""
    if pid in gone:
        return False
    if os.waitpid(pid, os.WNOHANG) == (0, 0):
        return True
    gone.add(pid)
    return False


read_end, write_end = os.pipe()
children = []
for index in range(CHILDREN):
    pid = os.fork()
    if pid == 0:
        os.close(read_end)
        hold(write_end, index)
        os._exit(0)
    children.append(pid)
os.close(write_end)
said = set()
deadline = time.monotonic() + 60.0
while time.monotonic() < deadline:
    ready, _, _ = select.select([read_end], [], [], 0.5)
    if ready:
        data = os.read(read_end, 8)
        if not data:  # every child's end closed: they said all they will
            break
        said |= set(data)
    if all(i in said or not alive(pid) for i, pid in enumerate(children)):  # each holds its block or is gone
        break
holding = sum(1 for i in said if alive(children[i]))  # still alive, holding its block
for pid in children:
    if alive(pid):
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
print(f"children holding 700 MiB at once: {holding} of {CHILDREN}", flush=True)

started = []
for _ in range(MOST_PROCESSES):
    try:
        pid = os.fork()
    except OSError:
        break
    if pid == 0:
        time.sleep(120)
        os._exit(0)
    started.append(pid)
for pid in started:
    os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
print(f"processes started: {len(started)} of {MOST_PROCESSES}", flush=True)
