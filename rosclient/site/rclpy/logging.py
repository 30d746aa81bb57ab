"""rclpy.logging: a node's logger prints `[LEVEL] [time] [name]: msg` (stderr) and publishes the
line on /rosout as rcl_interfaces/Log."""
from __future__ import annotations

import os
import sys
import time
from typing import Any

from rosclient import process
from rclpy.impl.logging_severity import LoggingSeverity


_loggers: dict[str, "RcutilsLogger"] = {}


class RcutilsLogger:
    def __init__(self, name: str = "") -> None:
        self.name = name
        self.level = LoggingSeverity.INFO  # the effective level
        self.set_to = LoggingSeverity.UNSET  # the level set on this logger (rcutils': UNSET until one is)
        self._once: set = set()
        self._last: dict = {}
        self._skipped: set = set()

    def get_child(self, name: str) -> "RcutilsLogger":
        return get_logger(f"{self.name}.{name}" if self.name else name)

    def set_level(self, level: Any) -> None:
        self.set_to = LoggingSeverity(level)
        self.level = self.set_to if self.set_to != LoggingSeverity.UNSET else LoggingSeverity.INFO

    def get_effective_level(self) -> LoggingSeverity:
        return self.level

    def is_enabled_for(self, severity: Any) -> bool:
        return severity >= self.level

    def log(self, message: Any, severity: Any, **kwargs: Any) -> bool:
        severity = LoggingSeverity(severity)
        if severity < self.level:
            return False
        caller = sys._getframe(2)
        key = (caller.f_code.co_filename, caller.f_lineno)
        if kwargs.get("once"):
            if key in self._once:
                return False
            self._once.add(key)
        if kwargs.get("skip_first") and key not in self._skipped:
            self._skipped.add(key)
            return False
        period = kwargs.get("throttle_duration_sec")
        if period:
            now = time.monotonic()
            if now - self._last.get(key, -1e18) < period:
                return False
            self._last[key] = now
        stamp = time.time_ns()
        name = severity.name
        print(f"[{name}] [{stamp // 10**9}.{stamp % 10**9:09d}] [{self.name}]: {message}", file=sys.stderr, flush=True)
        process.rosout({"stamp": {"sec": stamp // 10**9, "nanosec": stamp % 10**9}, "level": int(severity),
                        "name": self.name, "msg": str(message), "file": os.path.basename(caller.f_code.co_filename),
                        "function": caller.f_code.co_name, "line": caller.f_lineno}, "rcl_interfaces/msg/Log")
        return True

    def debug(self, message: Any, **kwargs: Any) -> bool:
        return self.log(message, LoggingSeverity.DEBUG, **kwargs)

    def info(self, message: Any, **kwargs: Any) -> bool:
        return self.log(message, LoggingSeverity.INFO, **kwargs)

    def warning(self, message: Any, **kwargs: Any) -> bool:
        return self.log(message, LoggingSeverity.WARN, **kwargs)

    warn = warning

    def error(self, message: Any, **kwargs: Any) -> bool:
        return self.log(message, LoggingSeverity.ERROR, **kwargs)

    def fatal(self, message: Any, **kwargs: Any) -> bool:
        return self.log(message, LoggingSeverity.FATAL, **kwargs)


def get_logger(name: str) -> RcutilsLogger:
    if name not in _loggers:
        _loggers[name] = RcutilsLogger(name)
    return _loggers[name]


def set_logger_level(name: str, level: Any) -> None:
    get_logger(name).set_level(level)
