"""rospy.rostime: ROS time. The lab's programs run on wall-clock time (the lab publishes no /clock),
so `Time.now()` is the wall clock, as rospy's with use_sim_time false."""

from __future__ import annotations

import time

import genpy


class Duration(genpy.Duration):
    __slots__ = ()

    def __repr__(self) -> str:
        return f"rospy.Duration[{self.to_nsec()}]"


class Time(genpy.Time):
    __slots__ = ()

    @classmethod
    def now(cls) -> Time:
        return cls(0, time.time_ns())

    def __repr__(self) -> str:
        return f"rospy.Time[{self.to_nsec()}]"

    def __sub__(self, other: object) -> object:  # a difference of times is rospy's Duration
        result = super().__sub__(other)
        return Duration(0, result.to_nsec()) if isinstance(result, genpy.Duration) else result


def get_rostime() -> Time:
    return Time.now()


def get_time() -> float:
    return time.time()


def is_wallclock() -> bool:
    return True


def is_rostime_initialized() -> bool:
    return True
