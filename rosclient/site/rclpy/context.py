"""rclpy.context.Context: whether ROS is initialised in this program, and the one condition every
wait of an executor sleeps on.

Everything that can make an executor's entity ready (a message, a service request, a client's
response, a future completed, a task created, a guard condition triggered, a timer created or reset,
a node added, the shutdown) calls `wake()`: the waits look again. The program's connection to the lab
is shared by every context (rosclient/process.py); a context shut down stops its executors.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from rosclient import process

CONDITION = threading.Condition()  # held while an executor looks for ready entities or waits
_generation = [0]  # how many times something woke the waits (a wake between a look and a wait is not lost)


def wake() -> None:
    with CONDITION:
        _generation[0] += 1
        CONDITION.notify_all()


def generation() -> int:
    """The wake count (read under CONDITION)."""
    return _generation[0]


process.on_shutdown(wake)  # the program's end (rclpy.shutdown, a signal, the lab gone) stops every wait


class Context:
    def __init__(self) -> None:
        self._initialized = False
        self._shut_down = False
        self._callbacks: list[Callable[[], None]] = []
        self._lock = threading.Lock()

    def init(self, args: list[str] | None = None, *, initialize_logging: bool = True, domain_id: int | None = None) -> None:
        with self._lock:
            if self._initialized and not self._shut_down:
                raise RuntimeError("Context.init() must only be called once")
            self._initialized, self._shut_down = True, False
        process.connection()

    def ok(self) -> bool:
        return self._initialized and not self._shut_down and process.ok()

    def _shutdown(self) -> None:
        with self._lock:
            self._shut_down = True
            callbacks, self._callbacks = self._callbacks, []
        for callback in callbacks:
            callback()
        wake()
        if self is _DEFAULT:
            process.close()

    def shutdown(self) -> None:
        if not self._initialized:
            raise RuntimeError("Context must be initialized before it can be shutdown")
        if not self.ok():
            raise RuntimeError("Context.shutdown() called on a context that is already shut down")
        self._shutdown()

    def try_shutdown(self) -> None:
        if self._initialized and not self._shut_down:
            self._shutdown()

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        with self._lock:
            self._callbacks.append(callback)

    def get_domain_id(self) -> int:
        return 0

    def __enter__(self) -> Context:
        return self

    def __exit__(self, *exc: object) -> None:
        self.try_shutdown()


_DEFAULT = Context()


def default_context() -> Context:
    return _DEFAULT
