"""What an executor waits on (rclpy's wait set, over rosbridge): an entity of a node — a
subscription, a timer, a service, a client, a guard condition, a waitable (an action server or
client) — is *ready* when it holds work (a message, a request, a response, a due time, a trigger),
and *taking* from it removes ONE piece of that work and gives the callback to run with it.

Data arrives on the connection's reader thread; the entity stores it under the context's condition
and wakes the executors (rclpy/context.py). rclpy/executors.py looks at every entity of its nodes in
each wait round."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import Any

from rclpy.callback_groups import CallbackGroup

# what a take gives: the callback's call with its data, a coroutine function when the callback is one
Call = Callable[[], Awaitable[Any] | Any]


class Entity:
    callback_group: CallbackGroup
    _executor_event = False  # a handler of the executor holds it (made, not yet run): not offered again

    def _is_ready(self) -> bool:
        """Whether a take would find work (called with the context's condition held)."""
        raise NotImplementedError

    def _take(self) -> Call | None:
        """One piece of work's callback (None when another took it first)."""
        raise NotImplementedError

    def _due(self) -> float | None:
        """When (time.monotonic) the entity becomes ready by itself: a timer's next call."""
        return None


async def await_or_execute(callback: Callable[..., Any], *args: Any) -> Any:
    """A callback's result: awaited when it is a coroutine function, called otherwise (rclpy's rule)."""
    import inspect

    if inspect.iscoroutinefunction(callback):
        return await callback(*args)
    result = callback(*args)
    if inspect.isawaitable(result):  # a callable object whose __call__ is async, a functools.partial of one
        return await result
    return result
