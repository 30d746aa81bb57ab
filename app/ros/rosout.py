"""/rosout: every node's log lines and the lab's own, as ROS 2 publishes them (rcl_interfaces/Log)
and ROS 1 did (rosgraph_msgs/Log; a ROS 1 client advertises, publishes and subscribes that type).

One line is a LogLine; `Rosout` keeps the newest MAX_LINES and hands each new line to its
listeners (the rosbridge streams, the HTTP stream, the dashboard's console through GET /log).
Levels are named as rcl_interfaces has them (DEBUG, INFO, WARN, ERROR, FATAL); the numbers
differ between the two message types and are converted here, nowhere else."""

from __future__ import annotations

import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace

from interfaces.json_value import JSON

TOPIC = "/rosout"
TYPE = "rcl_interfaces/Log"
ROS1_TYPE = "rosgraph_msgs/Log"
TYPES = (TYPE, ROS1_TYPE)
LEVELS = {"DEBUG": 10, "INFO": 20, "WARN": 30, "ERROR": 40, "FATAL": 50}  # rcl_interfaces/Log
ROS1_LEVELS = {"DEBUG": 1, "INFO": 2, "WARN": 4, "ERROR": 8, "FATAL": 16}  # rosgraph_msgs/Log
MAX_LINES = 1000  # kept for GET /log and the console
MAX_TEXT = 10_000  # characters of a message (longer is cut)


class BadLogMessage(ValueError):
    """A published log message that is not one (the reason names the field)."""


@dataclass(frozen=True)
class LogLine:
    stamp: float  # s (the server's wall clock for the lab's lines; a node's own stamp for its lines)
    level: str  # DEBUG, INFO, WARN, ERROR, FATAL
    node: str  # the logger's name, e.g. "cooperative_lifting", "/keytwist_param"
    msg: str
    file: str = ""
    function: str = ""
    line: int = 0
    seq: int = 0  # the server's count of lines, in the order they came (GET /log?after_seq=)

    def as_dict(self) -> dict:
        """GET /log's shape: stamp, node, level, msg (and where it was logged)."""
        return asdict(self)

    def message(self, type_name: str = TYPE) -> dict:
        """The line as a message of `type_name` (rcl_interfaces/Log or rosgraph_msgs/Log)."""
        sec = int(self.stamp)
        nanosec = min(int(round((self.stamp - sec) * 1e9)), 999_999_999)
        if type_name == ROS1_TYPE:
            return {
                "header": {"seq": 0, "stamp": {"secs": sec, "nsecs": nanosec}, "frame_id": ""},
                "level": ROS1_LEVELS[self.level],
                "name": self.node,
                "msg": self.msg,
                "file": self.file,
                "function": self.function,
                "line": self.line,
                "topics": [],
            }
        return {
            "stamp": {"sec": sec, "nanosec": nanosec},
            "level": LEVELS[self.level],
            "name": self.node,
            "msg": self.msg,
            "file": self.file,
            "function": self.function,
            "line": self.line,
        }


def _stamp(stamp: JSON) -> float:
    """builtin_interfaces/Time (sec, nanosec) or ROS 1's (secs, nsecs) -> s; absent: now."""
    if not isinstance(stamp, dict) or not stamp:
        return time.time()
    parts = [stamp.get("sec", stamp.get("secs", 0)), stamp.get("nanosec", stamp.get("nsecs", 0))]
    numbers = [float(v) for v in parts if not isinstance(v, bool) and isinstance(v, (int, float))]
    if len(numbers) != 2 or not all(math.isfinite(v) for v in numbers):
        raise BadLogMessage("field 'stamp' must hold numbers sec and nanosec")
    return numbers[0] + numbers[1] * 1e-9


def from_message(msg: dict, type_name: str, node: str) -> LogLine:
    """A published rcl_interfaces/Log or rosgraph_msgs/Log as a LogLine; `node` names it when the
    message's `name` is empty. BadLogMessage names the field that is wrong."""
    levels = ROS1_LEVELS if type_name == ROS1_TYPE else LEVELS
    level = msg.get("level", levels["INFO"])
    names = {number: name for name, number in levels.items()}
    if isinstance(level, bool) or level not in names:
        raise BadLogMessage(f"field 'level' must be one of {sorted(names)} ({type_name}), got {str(level)[:20]}")
    for key in ("name", "msg", "file", "function"):
        if not isinstance(msg.get(key, ""), str):
            raise BadLogMessage(f"field '{key}' must be a string")
    line = msg.get("line", 0)
    if isinstance(line, bool) or not isinstance(line, int):
        raise BadLogMessage("field 'line' must be an integer")
    stamp = _stamp(
        msg.get("header", {}).get("stamp")
        if type_name == ROS1_TYPE and isinstance(msg.get("header"), dict)
        else msg.get("stamp")
    )
    return LogLine(
        stamp,
        names[level],
        (msg.get("name") or node)[:256],
        msg.get("msg", "")[:MAX_TEXT],
        msg.get("file", "")[:256],
        msg.get("function", "")[:256],
        line,
    )


class Rosout:
    """The newest MAX_LINES lines; each new line goes to every listener (called on the logging
    thread: a listener hands it on, it never blocks)."""

    def __init__(self, max_lines: int = MAX_LINES) -> None:
        self.lines: deque[LogLine] = deque(maxlen=max_lines)
        self._listeners: list[Callable[[LogLine], None]] = []
        self._lock = threading.Lock()
        self._count = 0

    def log(self, node: str, msg: str, level: str = "INFO") -> None:
        """One of the lab's own lines."""
        self.publish(LogLine(time.time(), level, node, msg[:MAX_TEXT]))

    def publish(self, line: LogLine) -> None:
        with self._lock:
            self._count += 1
            line = replace(line, seq=self._count)
            self.lines.append(line)
            listeners = list(self._listeners)
        for listener in listeners:
            try:
                listener(line)
            except Exception:  # noqa: BLE001 - a listener that is gone does not stop the others
                pass

    def recent(self) -> list[LogLine]:
        with self._lock:
            return list(self.lines)

    def listen(self, listener: Callable[[LogLine], None]) -> Callable[[], None]:
        """Call `listener(line)` for each new line; returns the function that stops it."""
        with self._lock:
            self._listeners.append(listener)

        def stop() -> None:
            with self._lock:
                if listener in self._listeners:
                    self._listeners.remove(listener)

        return stop
