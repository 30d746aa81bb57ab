"""Waiting for a condition in tests: polls, never asserts on how long it took."""
import os
import time


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
