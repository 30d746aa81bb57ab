"""rospy.client: init_node, spin, the parameter server (the lab's, through rosapi), and the other
calls a node makes of its environment. Parameter names resolve as topic names do
(rospy/names.py): `~x` private, `x` in the node's namespace, `/x` global."""

from __future__ import annotations

import json
import logging
import os
import signal
import sys
import threading
import time
from typing import Any

from genpy import TVal

from rosclient import process
from rosclient.connection import RosbridgeError
from rospy import core, names
from rospy.core import DEBUG, ERROR, FATAL, INFO, WARN
from rospy.exceptions import ROSException, ROSInitException

__all__ = ["DEBUG", "INFO", "WARN", "ERROR", "FATAL"]


def init_node(
    name: str,
    argv: list[str] | None = None,
    anonymous: bool = False,
    log_level: int | None = None,
    disable_rostime: bool = False,
    disable_rosout: bool = False,
    disable_signals: bool = False,
    xmlrpc_port: int = 0,
    tcpros_port: int = 0,
) -> None:
    """Name this program's node: its namespace from `__ns:=` (a launch file's <group ns>) or
    $ROS_NAMESPACE, its base name `name` (or `__name:=`); `_x:=v` arguments set its private
    parameters, `a:=b` remaps names; the lab is told the node's name."""
    if core.is_initialized():
        raise ROSException(f"rospy.init_node() has already been called with different arguments: {names.get_name()}")
    args = sys.argv if argv is None else argv
    mappings = names.load_mappings(args)
    name = mappings.get("__name", name)
    if not name or "/" in name.strip("/"):
        raise ValueError("namespaces are not allowed in node names")
    if name.startswith("~"):
        raise ValueError("private names are not allowed in node names")
    base = name.strip("/")
    if anonymous:
        base = f"{base}_{os.getpid()}_{int(time.time() * 1000)}"
    ns = names.make_global_ns(mappings.get("__ns") or os.environ.get("ROS_NAMESPACE", ""))
    names.set_caller_id(ns + base, mappings)
    core.set_initialized(log_level, not disable_rosout)
    process.connection()
    process.declare_node(names.get_name())
    if not disable_signals and threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, lambda signum, frame: core.signal_shutdown("keyboard interrupt"))
        signal.signal(signal.SIGTERM, lambda signum, frame: core.signal_shutdown("terminated"))
    for arg in args[1:]:  # _name:=value sets the private parameter ~name
        if ":=" in arg:
            key, value = arg.split(":=", 1)
            if key.startswith("_") and not key.startswith("__"):
                set_param("~" + key[1:], process.parse_value(value))
    _advertise_logger_services()


def _advertise_logger_services() -> None:
    """roscpp's logger services, which rospy's init_node advertises for every node: `~get_loggers`
    (each logger of the program with its level) and `~set_logger_level` (a level by name; rosout's is
    the node's loginfo & co.)."""
    from roscpp.msg import Logger
    from roscpp.srv import GetLoggers, GetLoggersResponse, SetLoggerLevel, SetLoggerLevelResponse

    from rospy.impl.tcpros_service import Service
    from rospy.service import ServiceException

    def get_loggers(request: Any) -> Any:
        known = [core.ROSOUT_LOGGER, *(n for n in logging.Logger.manager.loggerDict if n != core.ROSOUT_LOGGER)]
        return GetLoggersResponse(loggers=[Logger(name=n, level=core.LEVEL_NAMES[core.logger_level(n)]) for n in known])

    def set_logger_level(request: Any) -> Any:
        level = {name: number for number, name in core.LEVEL_NAMES.items()}.get(request.level.upper())
        if level is None:  # rospy answers, and logs the bad level
            core.logerr(f"Bad logging level: {request.level.upper()}")
        else:
            core.set_logger_level(request.logger, level)
        return SetLoggerLevelResponse()

    try:
        Service("~get_loggers", GetLoggers, get_loggers)
        Service("~set_logger_level", SetLoggerLevel, set_logger_level)
    except ServiceException:  # a node of this name runs already (ROS 1's master would shut it down, the
        pass  # lab does not): the program's own services say so, as they did before these were advertised


def _require_node(what: str) -> None:
    if not core.is_initialized():
        raise ROSInitException(f"{what}: call rospy.init_node() first")


def spin() -> None:
    """Wait until the node shuts down (Ctrl+C); callbacks run on their own threads meanwhile."""
    _require_node("rospy.spin")
    try:
        while not process.shutdown_event.wait(0.2):
            pass
    except KeyboardInterrupt:
        core.signal_shutdown("keyboard interrupt")


def myargv(argv: list[str] | None = None) -> list[str]:
    """argv without ROS remapping arguments (name:=value)."""
    return [a for a in (sys.argv if argv is None else argv) if ":=" not in a]


def get_master() -> Any:
    return process.connection()


def get_published_topics(namespace: str = "/") -> list[list[str]]:
    """[topic, type] of every topic the lab knows under `namespace`."""
    answer = _rosapi("topics", {})
    prefix = names.make_global_ns(namespace)
    return [[t, ty] for t, ty in zip(answer.get("topics", []), answer.get("types", [])) if t.startswith(prefix)]


def wait_for_message(topic: str, topic_type: Any, timeout: float | TVal | None = None) -> Any:
    from rospy.topics import Subscriber

    got: list[Any] = []
    event = threading.Event()

    def take(msg: Any) -> None:
        if not got:
            got.append(msg)
            event.set()

    seconds = timeout.to_sec() if isinstance(timeout, TVal) else timeout
    sub = Subscriber(topic, topic_type, take)
    try:
        if not event.wait(seconds) or not got:
            raise ROSException(f"timeout exceeded while waiting for message on topic {topic}")
        return got[0]
    finally:
        sub.unregister()


# --- parameters (the lab's parameter server, through rosapi) ------------------------------------
class _Unspecified:
    pass


_unspecified = _Unspecified()


def _rosapi(service: str, args: dict[str, Any]) -> dict[str, Any]:
    try:
        answer: dict[str, Any] = process.connection().call_service(f"/rosapi/{service}", args, timeout=10)
        return answer
    except RosbridgeError as exc:
        raise ROSException(f"parameter server: {exc}") from None


def has_param(param_name: str) -> bool:
    return bool(_rosapi("has_param", {"name": names.resolve_name(param_name)}).get("exists"))


def get_param(param_name: str, default: Any = _unspecified) -> Any:
    """The value; the default when it is not set; KeyError when neither."""
    name = names.resolve_name(param_name)
    if not has_param(name):
        if default is _unspecified:
            raise KeyError(param_name)
        return default
    return json.loads(_rosapi("get_param", {"name": name, "default_value": ""})["value"])


def get_param_cached(param_name: str, default: Any = _unspecified) -> Any:
    return get_param(param_name, default)


def set_param(param_name: str, param_value: Any) -> None:
    _rosapi("set_param", {"name": names.resolve_name(param_name), "value": json.dumps(param_value)})


def delete_param(param_name: str) -> None:
    name = names.resolve_name(param_name)
    if not has_param(name):
        raise KeyError(param_name)
    _rosapi("delete_param", {"name": name})


def get_param_names() -> list[str]:
    return list(_rosapi("get_param_names", {}).get("names", []))


def search_param(param_name: str) -> str | None:
    """The parameter server's searchParam: the key looked for in the node's namespace, then in each
    namespace above it, up to the root; the first one set (its full name), else None."""
    if names.is_global(param_name):
        return param_name if has_param(param_name) else None
    if names.is_private(param_name):
        raise ValueError(f"search_param: a private name cannot be searched for: {param_name}")
    first = param_name.strip("/").split("/")[0]
    namespace = names.get_namespace()
    while True:
        if has_param(names.ns_join(namespace, first)):
            return names.ns_join(namespace, param_name.strip("/"))
        if namespace == names.SEP:
            return None
        namespace = names.namespace(namespace)
