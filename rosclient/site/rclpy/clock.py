"""rclpy.clock.Clock (the wall clock)."""
from __future__ import annotations

import time as _time
from enum import IntEnum


class ClockType(IntEnum):
    UNINITIALIZED = 0
    ROS_TIME = 1
    SYSTEM_TIME = 2
    STEADY_TIME = 3


class Clock:
    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        self.clock_type = clock_type

    def now(self):
        from rclpy.time import Time

        return Time(nanoseconds=_time.time_ns(), clock_type=self.clock_type)

    def sleep_for(self, duration) -> bool:
        _time.sleep(duration.nanoseconds / 1e9)
        return True


class ROSClock(Clock):
    def __init__(self) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)
