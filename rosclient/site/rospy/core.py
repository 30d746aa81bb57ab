"""rospy.core: the node's state (initialized, shut down, its hooks) and its logging (the console,
and /rosout once the node is connected, as rosgraph_msgs/Log lines)."""

from __future__ import annotations

import logging
import math
import os
import sys
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any

from rosclient import process
from rospy import names

DEBUG, INFO, WARN, ERROR, FATAL = 1, 2, 4, 8, 16  # rosgraph_msgs/Log levels
LEVEL_NAMES = {DEBUG: "DEBUG", INFO: "INFO", WARN: "WARN", ERROR: "ERROR", FATAL: "FATAL"}
_PYTHON_LEVELS = {DEBUG: logging.DEBUG, INFO: logging.INFO, WARN: logging.WARNING, ERROR: logging.ERROR, FATAL: logging.CRITICAL}

_state: dict[str, Any] = {"initialized": False, "level": INFO, "rosout": True, "topics_closed": False}
_shutdown_hooks: list[Callable[..., Any]] = []
_hooks_lock = threading.Lock()


def is_initialized() -> bool:
    return bool(_state["initialized"])


def set_initialized(level: int | None, rosout: bool) -> None:
    _state.update(initialized=True, rosout=rosout)
    if level is not None:
        _state["level"] = level


def is_shutdown() -> bool:
    return process.shutdown_event.is_set()


def is_shutdown_requested() -> bool:
    return process.shutdown_event.is_set()


def on_shutdown(hook: Callable[..., Any]) -> None:
    with _hooks_lock:
        _shutdown_hooks.append(hook)


def signal_shutdown(reason: str) -> None:
    """The node ends: spin() returns, sleep() raises ROSInterruptException, the hooks run, then
    the topics close (as rospy, a hook may still publish: its message goes out)."""
    if process.shutdown_event.is_set():
        return
    process.shutdown(reason)
    with _hooks_lock:
        hooks = list(_shutdown_hooks)
    for hook in hooks:
        try:
            hook()
        except Exception:  # noqa: BLE001 - rospy logs a failing hook and goes on
            traceback.print_exc()
    _state["topics_closed"] = True


def topics_closed() -> bool:
    return bool(_state["topics_closed"])


def get_node_uri() -> str:
    return process.connection().url


# --- logging ------------------------------------------------------------------------------------
ROSOUT_LOGGER = "rosout"  # the logger rospy's loginfo & co. write to (its level: init_node's log_level)


def logger_level(name: str) -> int:
    """A logger's level as rosgraph_msgs/Log numbers it: the node's own for rosout, else Python's."""
    if name == ROSOUT_LOGGER:
        return int(_state["level"])
    python = logging.getLogger(name).getEffectiveLevel()
    return min((level for level, value in _PYTHON_LEVELS.items() if value >= python), default=FATAL)


def set_logger_level(name: str, level: int) -> None:
    """`name`'s level set (rosout's is the node's own: its loginfo & co. below it print nothing)."""
    logging.getLogger(name).setLevel(_PYTHON_LEVELS[level])
    if name == ROSOUT_LOGGER:
        _state["level"] = level


def _log(level: int, msg: Any, *args: Any, **kwargs: Any) -> None:
    text = str(msg) % args if args else str(msg)
    if level < _state["level"]:
        return
    now = time.time()
    stream = sys.stdout if level <= INFO else sys.stderr
    print(f"[{LEVEL_NAMES[level]}] [{now:.6f}]: {text}", file=stream, flush=True)
    if _state["initialized"] and _state["rosout"]:
        caller = sys._getframe(2)
        process.rosout(
            {
                "header": {"stamp": process.stamp_now(), "frame_id": ""},
                "level": level,
                "name": names.get_name(),
                "msg": text,
                "file": os.path.basename(caller.f_code.co_filename),
                "function": caller.f_code.co_name,
                "line": caller.f_lineno,
                "topics": [],
            },
            "rosgraph_msgs/Log",
        )


def logdebug(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(DEBUG, msg, *args)


def loginfo(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(INFO, msg, *args)


def logwarn(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(WARN, msg, *args)


def logerr(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(ERROR, msg, *args)


def logfatal(msg: Any, *args: Any, **kwargs: Any) -> None:
    _log(FATAL, msg, *args)


logwarning = logwarn
logerror = logerr
logout = loginfo

_throttled: dict[tuple[str, int], float] = {}
_said_once: set[tuple[str, int]] = set()


def _throttle(level: int, period: float, msg: Any, *args: Any) -> None:
    caller = sys._getframe(2)
    key = (caller.f_code.co_filename, caller.f_lineno)
    now = time.monotonic()
    if now - _throttled.get(key, -math.inf) >= period:
        _throttled[key] = now
        _log(level, msg, *args)


def _once(level: int, msg: Any, *args: Any) -> None:
    caller = sys._getframe(2)
    key = (caller.f_code.co_filename, caller.f_lineno)
    if key not in _said_once:
        _said_once.add(key)
        _log(level, msg, *args)


def logdebug_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(DEBUG, period, msg, *args)


def loginfo_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(INFO, period, msg, *args)


def logwarn_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(WARN, period, msg, *args)


def logerr_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(ERROR, period, msg, *args)


def logfatal_throttle(period: float, msg: Any, *args: Any) -> None:
    _throttle(FATAL, period, msg, *args)


def logdebug_once(msg: Any, *args: Any) -> None:
    _once(DEBUG, msg, *args)


def loginfo_once(msg: Any, *args: Any) -> None:
    _once(INFO, msg, *args)


def logwarn_once(msg: Any, *args: Any) -> None:
    _once(WARN, msg, *args)


def logerr_once(msg: Any, *args: Any) -> None:
    _once(ERROR, msg, *args)


def logfatal_once(msg: Any, *args: Any) -> None:
    _once(FATAL, msg, *args)
