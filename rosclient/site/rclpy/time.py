"""rclpy.time.Time (wall clock: the lab's programs use no simulated /clock)."""
from __future__ import annotations

from typing import Any


class Time:
    def __init__(self, *, seconds: float = 0, nanoseconds: int = 0, clock_type: Any = None) -> None:
        self.nanoseconds = int(seconds * 10**9) + int(nanoseconds)
        self.clock_type = clock_type

    def seconds_nanoseconds(self) -> tuple[int, int]:
        return divmod(self.nanoseconds, 10**9)

    def to_msg(self):
        from builtin_interfaces.msg import Time as TimeMsg

        sec, nanosec = self.seconds_nanoseconds()
        return TimeMsg(sec=sec, nanosec=nanosec)

    @classmethod
    def from_msg(cls, msg: Any, clock_type: Any = None) -> "Time":
        return cls(seconds=msg.sec, nanoseconds=msg.nanosec)

    def __sub__(self, other: Any):
        from rclpy.duration import Duration

        if isinstance(other, Time):
            return Duration(nanoseconds=self.nanoseconds - other.nanoseconds)
        return Time(nanoseconds=self.nanoseconds - other.nanoseconds)

    def __add__(self, other: Any) -> "Time":
        return Time(nanoseconds=self.nanoseconds + other.nanoseconds)

    def __eq__(self, other: Any) -> bool:
        return isinstance(other, Time) and other.nanoseconds == self.nanoseconds

    def __lt__(self, other: "Time") -> bool:
        return self.nanoseconds < other.nanoseconds

    def __le__(self, other: "Time") -> bool:
        return self.nanoseconds <= other.nanoseconds

    def __hash__(self) -> int:
        return hash(self.nanoseconds)

    def __repr__(self) -> str:
        return f"Time(nanoseconds={self.nanoseconds})"
