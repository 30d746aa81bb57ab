"""rclpy.task: Future (a result that comes later) and Task (a callback or coroutine an executor runs,
itself a Future of its result), as rclpy has them.

A future's done callbacks run where it completes, or as tasks of its executor when it has one
(`_set_executor`); completing a future wakes every executor (rclpy/context.py), so a task awaiting it
runs again in the next wait round. `await future` inside an `async def` callback yields until the
future is done.
"""

from __future__ import annotations

import inspect
import threading
from collections.abc import Callable, Coroutine, Generator
from typing import TYPE_CHECKING, Any

from rclpy.context import wake

if TYPE_CHECKING:
    from rclpy.executors import Executor


class Future:
    def __init__(self, *, executor: Executor | None = None) -> None:
        self._state_lock = threading.Lock()
        self._done = False
        self._cancelled = False
        self._result: Any = None
        self._exception: BaseException | None = None
        self._exception_fetched = False
        self._callbacks: list[Callable[[Future], Any]] = []
        self._executor = executor

    def __await__(self) -> Generator[None, None, Any]:
        while not self._done:
            yield
        return self.result()

    def cancel(self) -> None:
        with self._state_lock:
            if self._done:
                return
            self._cancelled = True
        self._complete()

    def cancelled(self) -> bool:
        return self._cancelled

    def done(self) -> bool:
        return self._done

    def result(self) -> Any:
        """The result (None while not done); raises the exception the future ended with."""
        if self._exception is not None:
            self._exception_fetched = True
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        self._exception_fetched = True
        return self._exception

    def set_result(self, result: Any) -> None:
        with self._state_lock:
            self._result = result
            self._cancelled = False
        self._complete()

    def set_exception(self, exception: BaseException) -> None:
        with self._state_lock:
            self._exception = exception
            self._cancelled = False
        self._complete()

    def _complete(self) -> None:
        with self._state_lock:
            self._done = True
            callbacks, self._callbacks = self._callbacks, []
        for callback in callbacks:
            self._invoke(callback)
        wake()

    def _invoke(self, callback: Callable[[Future], Any]) -> None:
        if self._executor is not None:
            self._executor.create_task(callback, self)
        else:
            callback(self)

    def _set_executor(self, executor: Executor) -> None:
        self._executor = executor

    def add_done_callback(self, callback: Callable[[Future], Any]) -> None:
        with self._state_lock:
            if not self._done:
                self._callbacks.append(callback)
                return
        self._invoke(callback)

    def remove_done_callback(self, callback: Callable[[Future], Any]) -> bool:
        with self._state_lock:
            if callback in self._callbacks:
                self._callbacks.remove(callback)
                return True
        return False


class Task(Future):
    """A callback or a coroutine run by an executor; a coroutine runs until it awaits a future that
    is not done, and again in a later wait round (a coroutine is never run by two threads at once)."""

    def __init__(
        self,
        handler: Callable[..., Any] | Coroutine[Any, Any, Any],
        args: tuple[Any, ...] | None = None,
        kwargs: dict[str, Any] | None = None,
        executor: Executor | None = None,
    ) -> None:
        super().__init__(executor=executor)
        self._args, self._kwargs = args or (), kwargs or {}
        self._coroutine: Coroutine[Any, Any, Any] | None = None
        self._function: Callable[..., Any] | None = None
        if inspect.iscoroutine(handler):
            self._coroutine = handler
        elif inspect.iscoroutinefunction(handler):
            self._coroutine = handler(*self._args, **self._kwargs)
        else:
            assert callable(handler), f"a task runs a callable or a coroutine, not {handler!r}"
            self._function = handler
        self._executing = False
        self._scheduled = False  # handed to a MultiThreadedExecutor's pool, not yet run
        self._task_lock = threading.Lock()

    def __call__(self) -> None:
        """Run the task (a coroutine: until its next await of a future that is not done)."""
        if self._done or not self._task_lock.acquire(blocking=False):
            return
        try:
            if self._done:
                return
            self._executing = True
            if self._coroutine is not None:
                try:
                    self._coroutine.send(None)
                except StopIteration as end:
                    self.set_result(end.value)
                except Exception as exc:  # noqa: BLE001 - the task's outcome: raised by whoever takes its result
                    self.set_exception(exc)
            else:
                assert self._function is not None
                try:
                    self.set_result(self._function(*self._args, **self._kwargs))
                except Exception as exc:  # noqa: BLE001 - as above
                    self.set_exception(exc)
        finally:
            self._executing = False
            self._task_lock.release()

    def executing(self) -> bool:
        return self._executing

    def cancel(self) -> None:
        if self._coroutine is not None and not self._done and not self._executing:
            self._coroutine.close()
        super().cancel()
