"""rclpy (ROS 2's Python client library) over the lab's rosbridge endpoint.

init() connects to the lab and reads the program's `--ros-args` (-p name:=value, -p node:name:=value,
--params-file FILE, -r __node:=NAME, -r __ns:=NS); spin()/spin_once()/spin_until_future_complete()
run the nodes' callbacks on the calling thread (rclpy/executors.py). Ctrl+C raises
KeyboardInterrupt out of spin, as in rclpy. Differences from ROS 2: docs/ros-programs-client.md.
"""
from __future__ import annotations

import signal
import sys
import threading
from typing import Any

from app.rosclient import process

process.ensure_interfaces()

_state: dict[str, Any] = {"initialized": False, "arguments": None, "executor": None}


class Arguments:
    """What `--ros-args` says: parameter overrides (global and per node), the node's name and namespace,
    names remapped (`-r from:=to`)."""

    def __init__(self, ros_args: list[str]) -> None:
        self.parameters: dict[str, dict[str, Any]] = {}  # node ('' = every node) -> name -> value
        self.remapped_name: str | None = None
        self.namespace: str | None = None
        i = 0
        while i < len(ros_args):
            flag = ros_args[i]
            value = ros_args[i + 1] if i + 1 < len(ros_args) else None
            if flag in ("-p", "--param") and value and ":=" in value:
                key, text = value.split(":=", 1)
                node, _, name = key.rpartition(":")
                self.parameters.setdefault(node.strip("/"), {})[name] = process.parse_value(text)
                i += 2
            elif flag in ("-r", "--remap") and value and ":=" in value:
                key, text = value.split(":=", 1)
                if key.endswith("__node") or key.endswith("__name"):
                    self.remapped_name = text
                elif key.endswith("__ns"):
                    self.namespace = text
                else:  # a topic or service name remapped (from the default namespace)
                    process.remaps[process.resolve(key)] = process.resolve(text)
                i += 2
            elif flag == "--params-file" and value:
                self._params_file(value)
                i += 2
            else:
                i += 1

    def _params_file(self, path: str) -> None:
        import yaml

        with open(path, encoding="utf-8") as stream:
            data = yaml.safe_load(stream) or {}
        for node, body in data.items():
            values = (body or {}).get("ros__parameters", {})
            key = "" if node in ("/**", "**") else node.strip("/")
            self.parameters.setdefault(key, {}).update(_flatten(values))

    def parameters_for(self, fully_qualified: str, name: str) -> dict[str, Any]:
        out = dict(self.parameters.get("", {}))
        out.update(self.parameters.get(name, {}))
        out.update(self.parameters.get(fully_qualified.strip("/"), {}))
        return out


def _flatten(values: dict, prefix: str = "") -> dict[str, Any]:
    out = {}
    for key, value in values.items():
        if isinstance(value, dict):
            out.update(_flatten(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def _arguments(cli_args: list[str] | None, use_global: bool) -> Arguments:
    merged = Arguments([])
    sources = []
    if use_global and _state["arguments"] is not None:
        sources.append(_state["arguments"])
    if cli_args:
        sources.append(Arguments(process.program_args(["", *cli_args])[1] if "--ros-args" in cli_args else cli_args))
    for source in sources:
        for node, values in source.parameters.items():
            merged.parameters.setdefault(node, {}).update(values)
        merged.remapped_name = source.remapped_name or merged.remapped_name
        merged.namespace = source.namespace or merged.namespace
    return merged


def init(*, args: list[str] | None = None, context: Any = None, domain_id: int | None = None,
         signal_handler_options: Any = None) -> None:
    if _state["initialized"] and process.ok():
        raise RuntimeError("Context.init() must only be called once")
    _state["arguments"] = Arguments(process.program_args(sys.argv if args is None else args)[1])
    process.connection()
    _state["initialized"] = True
    if signal_handler_options != 0 and threading.current_thread() is threading.main_thread():
        # rclpy installs its own SIGINT handler (SignalHandlerOptions.ALL, the default), whatever the
        # program inherited: Ctrl+C is a KeyboardInterrupt out of spin even when the program was
        # started by a parent that ignores SIGINT (Python leaves an inherited SIG_IGN alone)
        signal.signal(signal.SIGINT, signal.default_int_handler)


def ok(*, context: Any = None) -> bool:
    return _state["initialized"] and process.ok()


def shutdown(*, context: Any = None, uncaught: bool = False) -> None:
    if not _state["initialized"]:
        raise RuntimeError("Context must be initialized before it can be shutdown")
    if not process.ok():
        raise RuntimeError("Context.shutdown() called on a context that is already shut down")
    process.close()


def try_shutdown(*, context: Any = None) -> None:
    if _state["initialized"] and process.ok():
        process.close()


def remove_ros_args(args: list[str] | None = None) -> list[str]:
    return process.program_args(sys.argv if args is None else args)[0]


def create_node(node_name: str, **kwargs: Any):
    from rclpy.node import Node

    return Node(node_name, **kwargs)


def get_global_executor():
    from rclpy.executors import SingleThreadedExecutor

    if _state["executor"] is None:
        _state["executor"] = SingleThreadedExecutor()
    return _state["executor"]


def _executor(node: Any, executor: Any):
    executor = executor or get_global_executor()
    executor.add_node(node)
    return executor


def spin_once(node: Any, *, executor: Any = None, timeout_sec: float | None = None) -> None:
    _executor(node, executor).spin_once(timeout_sec)


def spin(node: Any, executor: Any = None) -> None:
    _executor(node, executor).spin()


def spin_until_future_complete(node: Any, future: Any, executor: Any = None, timeout_sec: float | None = None) -> None:
    _executor(node, executor).spin_until_future_complete(future, timeout_sec)


def get_default_context():
    return None

