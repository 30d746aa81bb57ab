"""rclpy's executors: a node's callbacks (subscriptions, services, timers, futures of its clients,
parameter services) wait in its work queue and run INSIDE spin()/spin_once() on the spinning thread,
as rclpy runs them. MultiThreadedExecutor hands them to a pool of threads instead.
"""
from __future__ import annotations

import math
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable

from app.rosclient import process

WAKE = threading.Condition()  # a node got work (or a timer changed): spinners look again


class ExternalShutdownException(Exception):
    """The context was shut down while spinning."""


class ShutdownException(Exception):
    pass


class TimeoutException(Exception):
    pass


def post(node: Any, work: Callable[[], None]) -> None:
    """Queue a callback of `node` for its executor (from any thread)."""
    with WAKE:
        node._work.append(work)
        WAKE.notify_all()


class Executor:
    def __init__(self, *, context: Any = None) -> None:
        self._nodes: list[Any] = []
        self._lock = threading.Lock()

    def add_node(self, node: Any) -> bool:
        with self._lock:
            if node in self._nodes:
                return False
            self._nodes.append(node)
            node.executor = self
        return True

    def remove_node(self, node: Any) -> None:
        with self._lock:
            if node in self._nodes:
                self._nodes.remove(node)

    def get_nodes(self) -> list[Any]:
        return list(self._nodes)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        with self._lock:
            self._nodes.clear()
        return True

    def _next(self, timeout_sec: float | None) -> Callable[[], None] | None:
        """The next callback of this executor's nodes, waiting at most timeout_sec (None: forever)."""
        deadline = math.inf if timeout_sec is None or timeout_sec < 0 else time.monotonic() + timeout_sec
        with WAKE:
            while True:
                if process.shutdown_event.is_set():
                    return None
                now = time.monotonic()
                nodes = list(self._nodes)
                for node in nodes:
                    if node._work:
                        return node._work.popleft()
                due, timer = math.inf, None
                for node in nodes:
                    for t in node._timers:
                        if not t.is_canceled() and t._due < due:
                            due, timer = t._due, t
                if timer is not None and due <= now:
                    return timer._fire
                if now >= deadline:
                    return None
                WAKE.wait(min(due, deadline, now + 1.0) - now)

    def spin_once(self, timeout_sec: float | None = None) -> None:
        work = self._next(timeout_sec)
        if work is not None:
            work()

    def spin(self) -> None:
        while process.ok():
            self.spin_once()

    def spin_until_future_complete(self, future: Any, timeout_sec: float | None = None) -> None:
        deadline = None if timeout_sec is None or timeout_sec < 0 else time.monotonic() + timeout_sec
        while process.ok() and not future.done():
            if deadline is None:
                self.spin_once(0.1)
            else:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return
                self.spin_once(min(remaining, 0.1))

    def wake(self) -> None:
        with WAKE:
            WAKE.notify_all()

    def __enter__(self):
        return self

    def __exit__(self, *exc: Any) -> None:
        self.shutdown()


class SingleThreadedExecutor(Executor):
    pass


class MultiThreadedExecutor(Executor):
    """Callbacks on a pool of `num_threads` threads (callback groups are not told apart)."""

    def __init__(self, num_threads: int | None = None, *, context: Any = None) -> None:
        super().__init__(context=context)
        self._pool = ThreadPoolExecutor(max_workers=num_threads or 4, thread_name_prefix="rclpy-executor")

    def spin_once(self, timeout_sec: float | None = None) -> None:
        work = self._next(timeout_sec)
        if work is not None:
            self._pool.submit(_logged, work)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        self._pool.shutdown(wait=False)
        return super().shutdown(timeout_sec)


def _logged(work: Callable[[], None]) -> None:
    import traceback

    try:
        work()
    except Exception:  # noqa: BLE001 - a pool thread has no caller to raise to
        traceback.print_exc()
