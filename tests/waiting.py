"""Waiting for a condition in tests: polls, never asserts on how long it took."""
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
