"""rclpy.executors: run the callbacks of a set of nodes, as rclpy's executors do.

A *wait round* first runs the executor's pending tasks once each (coroutines waiting on a future,
`create_task`'s callables), then looks at every entity of its nodes (rclpy/_entity.py) and takes a
handler for each one that is ready — waitables, timers, subscriptions, guard conditions, clients,
services, in that order per node — so every ready entity gets one callback per round: a busy
subscription (ONE message per round) never starves a service, a timer or a client's response.
With nothing ready it sleeps until something wakes it (rclpy/context.py), the next timer is due or
the timeout ends.

A handler is a Task: it asks the entity's callback group whether it may begin, takes one piece of
work from the entity and runs its callback, awaiting it when it is a coroutine (`async def`): a
coroutine that awaits a future that is not done stays a pending task and goes on in a later round.
SingleThreadedExecutor runs the handlers on the spinning thread; MultiThreadedExecutor on a pool of
threads, where callback groups decide what may run together. An exception a callback raises
leaves spin, as in rclpy.
"""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable, Coroutine, Generator
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any

from rclpy import context as _context
from rclpy._entity import Entity
from rclpy.context import Context, default_context
from rclpy.task import Future, Task

if TYPE_CHECKING:
    from rclpy.node import Node


class ExternalShutdownException(Exception):
    """The context was shut down from outside while the executor waited (another thread, a signal)."""


class ShutdownException(Exception):
    """The executor was shut down."""


class TimeoutException(Exception):
    """The wait timed out."""


class ConditionReachedException(Exception):
    """The condition the wait was given became true (e.g. a future is done)."""


class TimeoutObject:
    def __init__(self, timeout: float) -> None:
        self.timeout = timeout


Handler = tuple[Task, Entity | None, "Node | None"]


def _timeout_s(timeout: float | TimeoutObject | None) -> float | None:
    value = timeout.timeout if isinstance(timeout, TimeoutObject) else timeout
    return None if value is None or value < 0 else float(value)


class Executor:
    def __init__(self, *, context: Context | None = None) -> None:
        self._context = context or default_context()
        self._nodes: list[Node] = []
        self._nodes_lock = threading.RLock()
        self._tasks: list[Handler] = []
        self._tasks_lock = threading.Lock()
        self._is_shutdown = False
        self._cb_iter: Generator[Handler, None, None] | None = None
        self._last_args: tuple[Any, ...] | None = None
        self._context.on_shutdown(self.wake)

    @property
    def context(self) -> Context:
        return self._context

    def create_task(self, callback: Callable[..., Any] | Coroutine[Any, Any, Any], *args: Any, **kwargs: Any) -> Task:
        """A callback or coroutine run during spin; the Task is a Future of its result."""
        task = Task(callback, args, kwargs, executor=self)
        with self._tasks_lock:
            self._tasks.append((task, None, None))
        self.wake()
        return task

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        self._is_shutdown = True
        self.wake()
        with self._nodes_lock:
            self._nodes.clear()
        self._cb_iter = None
        return True

    def add_node(self, node: Node) -> bool:
        with self._nodes_lock:
            if node in self._nodes:
                return False
            self._nodes.append(node)
            node.executor = self
        self.wake()
        return True

    def remove_node(self, node: Node) -> None:
        with self._nodes_lock:
            if node in self._nodes:
                self._nodes.remove(node)
        self.wake()

    def get_nodes(self) -> list[Node]:
        with self._nodes_lock:
            return list(self._nodes)

    def wake(self) -> None:
        _context.wake()

    def spin(self) -> None:
        while self._context.ok() and not self._is_shutdown:
            self.spin_once()

    def spin_once(self, timeout_sec: float | None = None) -> None:
        raise NotImplementedError

    def _spin_once_impl(self, timeout_sec: float | TimeoutObject | None, condition: Callable[[], bool]) -> None:
        raise NotImplementedError

    def spin_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        """Run callbacks until `future` is done, the context is shut down or timeout_sec passed."""
        future.add_done_callback(lambda _: self.wake())
        timeout = _timeout_s(timeout_sec)
        if timeout is None:
            while self._context.ok() and not future.done() and not self._is_shutdown:
                self._spin_once_impl(None, future.done)
            return
        end = time.monotonic() + timeout
        left = TimeoutObject(timeout)
        while self._context.ok() and not future.done() and not self._is_shutdown:
            self._spin_once_impl(left, future.done)
            now = time.monotonic()
            if now >= end:
                return
            left.timeout = end - now

    def spin_once_until_future_complete(self, future: Future, timeout_sec: float | TimeoutObject | None = None) -> None:
        future.add_done_callback(lambda _: self.wake())
        self._spin_once_impl(timeout_sec, future.done)

    # --- the wait rounds ----------------------------------------------------------------------
    def can_execute(self, entity: Entity) -> bool:
        return not entity._executor_event and entity.callback_group.can_execute(entity)

    def _make_handler(self, entity: Entity, node: Node) -> Task:
        entity._executor_event = True
        group = entity.callback_group

        async def handler() -> None:
            if self._is_shutdown or not group.beginning_execution(entity):
                entity._executor_event = False
                self.wake()
                return
            try:
                call = entity._take()
                entity._executor_event = False
                self.wake()
                if call is not None:
                    result = call()
                    if hasattr(result, "__await__"):
                        await result
            finally:
                group.ending_execution(entity)
                self.wake()

        task = Task(handler, executor=self)
        with self._tasks_lock:
            self._tasks.append((task, entity, node))
        return task

    def _ready(self, nodes: list[Node]) -> list[tuple[Entity, Node]]:
        """The entities ready now, in rclpy's order per node (called with the condition held)."""
        ready: list[tuple[Entity, Node]] = []
        for node in nodes:
            for kind in (node.waitables, node.timers, node.subscriptions, node.guards, node.clients, node.services):
                ready.extend((entity, node) for entity in kind if self.can_execute(entity) and entity._is_ready())
        return ready

    def _next_due(self, nodes: list[Node]) -> float:
        due = math.inf
        for node in nodes:
            for entity in (*node.timers, *node.waitables):  # timers, and the QoS events' handlers
                when = entity._due()
                if when is not None and self.can_execute(entity):
                    due = min(due, when)
        return due

    def _wait_for_ready_callbacks(
        self,
        timeout_sec: float | TimeoutObject | None = None,
        nodes: list[Node] | None = None,
        condition: Callable[[], bool] = lambda: False,
    ) -> Generator[Handler, None, None]:
        """Handlers ready to run (see the module's doc); raises TimeoutException, ShutdownException,
        ExternalShutdownException or ConditionReachedException when it ends without work."""
        timeout = _timeout_s(timeout_sec)
        deadline = math.inf if timeout is None else time.monotonic() + timeout
        yielded = False
        while not yielded and not self._is_shutdown and not condition():
            use = nodes if nodes is not None else self.get_nodes()
            with _context.CONDITION:
                seen = _context.generation()
            with self._tasks_lock:
                tasks = list(self._tasks)
            for task, entity, node in tasks:
                if not (task.executing() or task.done() or task._scheduled) and (node is None or node in use):
                    yielded = True
                    yield task, entity, node
            with self._tasks_lock:
                self._tasks = [t for t in self._tasks if not t[0].done()]
            with _context.CONDITION:
                while True:
                    if self._is_shutdown:
                        raise ShutdownException()
                    if not self._context.ok():
                        raise ExternalShutdownException()
                    ready = self._ready(use)
                    now = time.monotonic()
                    if ready or condition() or _context.generation() != seen or now >= deadline:
                        break
                    _context.CONDITION.wait(min(deadline, self._next_due(use), now + 1.0) - now)
            for entity, node in ready:
                if self.can_execute(entity):
                    yielded = True
                    yield self._make_handler(entity, node), entity, node
            if not yielded and (timeout == 0 or time.monotonic() >= deadline):
                raise TimeoutException()
        if self._is_shutdown:
            raise ShutdownException()
        if condition():
            raise ConditionReachedException()

    def wait_for_ready_callbacks(self, *args: Any, **kwargs: Any) -> Handler:
        """The next ready handler (the round's generator is kept between calls with the same arguments)."""
        while True:
            key = (args, tuple(sorted(kwargs.items())))
            if self._cb_iter is None or self._last_args != key:
                self._last_args = key
                self._cb_iter = self._wait_for_ready_callbacks(*args, **kwargs)
            try:
                return next(self._cb_iter)
            except StopIteration:
                self._cb_iter = None
            except BaseException:
                self._cb_iter = None
                raise

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.shutdown()


class SingleThreadedExecutor(Executor):
    """Runs the callbacks on the thread that spins."""

    def _spin_once_impl(self, timeout_sec: float | TimeoutObject | None = None,
                        condition: Callable[[], bool] = lambda: False) -> None:
        try:
            handler, _, _ = self.wait_for_ready_callbacks(timeout_sec, None, condition)
        except (ShutdownException, TimeoutException, ConditionReachedException):
            return
        handler()
        if handler.exception() is not None:
            raise handler.exception()  # type: ignore[misc]

    def spin_once(self, timeout_sec: float | None = None) -> None:
        self._spin_once_impl(timeout_sec)


class MultiThreadedExecutor(Executor):
    """Runs the callbacks on a pool of `num_threads` threads (default: the CPUs this process may
    use); a callback group decides which of its callbacks may run at the same time."""

    def __init__(self, num_threads: int | None = None, *, context: Context | None = None) -> None:
        super().__init__(context=context)
        if num_threads is None:
            num_threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 2)
        self._futures: list[Any] = []
        self._executor = ThreadPoolExecutor(max(1, num_threads), thread_name_prefix="rclpy-executor")

    def _spin_once_impl(self, timeout_sec: float | TimeoutObject | None = None,
                        condition: Callable[[], bool] = lambda: False) -> None:
        try:
            handler, _, _ = self.wait_for_ready_callbacks(timeout_sec, None, condition)
        except (ExternalShutdownException, ShutdownException, TimeoutException, ConditionReachedException):
            return
        handler._scheduled = True  # not offered again before a thread of the pool has run it
        self._futures.append(self._executor.submit(_run, handler))
        for future in self._futures[:]:
            if future.done():
                self._futures.remove(future)
                future.result()  # a callback's exception leaves spin

    def spin_once(self, timeout_sec: float | None = None) -> None:
        self._spin_once_impl(timeout_sec)

    def shutdown(self, timeout_sec: float | None = None, *, wait_for_threads: bool = True) -> bool:
        done = super().shutdown(timeout_sec)
        self._executor.shutdown(wait=wait_for_threads)
        return done


def _run(handler: Task) -> None:
    handler._scheduled = False
    handler()
    if handler.exception() is not None:
        raise handler.exception()  # type: ignore[misc]
