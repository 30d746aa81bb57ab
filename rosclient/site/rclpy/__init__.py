"""rclpy (ROS 2's Python client library) over the lab's rosbridge endpoint, as Jazzy and Rolling have
it: `with rclpy.init():` (init returns a context manager; Humble's plain `rclpy.init()` works too),
`rclpy.shutdown()`/`try_shutdown()`/`ok()`, `create_node`, and spin()/spin_once()/
spin_until_future_complete() on the global executor (rclpy/executors.py) or the one given.

init() connects to the lab and reads the program's `--ros-args` (rclpy/_arguments.py). Ctrl+C raises
KeyboardInterrupt out of spin, as in rclpy; SIGTERM shuts the context down, so spin raises
ExternalShutdownException. Differences from ROS 2: docs/ros-programs-client.md.
"""

from __future__ import annotations

import signal
import sys
import threading
from types import FrameType
from typing import TYPE_CHECKING, Any

from interfaces.sequences import use_typed
from rosclient import process
from rclpy import _arguments, utilities
from rclpy.context import Context, default_context
from rclpy.task import Future
from rclpy.utilities import get_default_context, get_rmw_implementation_identifier, ok, remove_ros_args

__all__ = ["Context", "Future", "Parameter", "SignalHandlerOptions", "create_node", "get_default_context",
           "get_global_executor", "get_rmw_implementation_identifier", "init", "ok", "remove_ros_args", "shutdown",
           "spin", "spin_once", "spin_until_future_complete", "try_shutdown"]

if TYPE_CHECKING:
    from rclpy.executors import Executor
    from rclpy.node import Node

process.ensure_interfaces()
use_typed()  # numeric arrays as rclpy's messages hold them: array.array, numpy (interfaces/sequences.py)

from rclpy.parameter import Parameter  # noqa: E402 - rclpy's top level exports it (the parameters tutorial)


class SignalHandlerOptions:
    NO, SIGINT, SIGTERM, ALL = 0, 1, 2, 3


def _on_sigterm(signum: int, frame: FrameType | None) -> None:
    """rclpy's SIGTERM handler: the contexts shut down, spin raises ExternalShutdownException."""
    default_context().try_shutdown()


class InitContextManager:
    """What init() returns: `with rclpy.init():` shuts the context down at the block's end."""

    def __init__(self, args: list[str] | None, context: Context | None, domain_id: int | None,
                 signal_handler_options: Any) -> None:
        self.context = context or default_context()
        if signal_handler_options is None:
            signal_handler_options = SignalHandlerOptions.ALL if self.context is default_context() else 0
        self.context.init(args, domain_id=domain_id)
        if self.context is default_context():
            _arguments.set_global(sys.argv if args is None else args)
        self.installed_signal_handlers = bool(signal_handler_options)
        if signal_handler_options and threading.current_thread() is threading.main_thread():
            if signal_handler_options in (SignalHandlerOptions.ALL, SignalHandlerOptions.SIGINT):
                # Ctrl+C is a KeyboardInterrupt out of spin even when the program was started by a
                # parent that ignores SIGINT (Python leaves an inherited SIG_IGN alone)
                signal.signal(signal.SIGINT, signal.default_int_handler)
            if signal_handler_options in (SignalHandlerOptions.ALL, SignalHandlerOptions.SIGTERM):
                signal.signal(signal.SIGTERM, _on_sigterm)

    def __enter__(self) -> InitContextManager:
        return self

    def __exit__(self, *exc: object) -> None:
        self.context.try_shutdown()


def init(*, args: list[str] | None = None, context: Context | None = None, domain_id: int | None = None,
         signal_handler_options: Any = None) -> InitContextManager:
    return InitContextManager(args, context, domain_id, signal_handler_options)


def shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    utilities.shutdown(context=context)


def try_shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    utilities.try_shutdown(context=context)


def create_node(node_name: str, **kwargs: Any) -> Node:
    from rclpy.node import Node

    return Node(node_name, **kwargs)


_executor: list[Executor] = []


def get_global_executor() -> Executor:
    if not _executor:
        from rclpy.executors import SingleThreadedExecutor

        _executor.append(SingleThreadedExecutor())
    return _executor[0]


def spin_once(node: Node, *, executor: Executor | None = None, timeout_sec: float | None = None) -> None:
    executor = executor or get_global_executor()
    try:
        executor.add_node(node)
        executor.spin_once(timeout_sec=timeout_sec)
    finally:
        executor.remove_node(node)


def spin(node: Node, executor: Executor | None = None) -> None:
    executor = executor or get_global_executor()
    try:
        executor.add_node(node)
        while executor.context.ok():
            executor.spin_once()
    finally:
        executor.remove_node(node)


def spin_until_future_complete(node: Node, future: Future, executor: Executor | None = None,
                               timeout_sec: float | None = None) -> None:
    executor = executor or get_global_executor()
    added = False
    try:
        added = executor.add_node(node)
        executor.spin_until_future_complete(future, timeout_sec)
    finally:
        if added:
            executor.remove_node(node)
