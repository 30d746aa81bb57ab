"""genpy's Time and Duration: whole seconds and nanoseconds (`secs`, `nsecs`), canonical (0 <= nsecs
< 1e9; a negative Duration keeps nsecs of its sign, as genpy's canon does), compared and hashed by
their nanoseconds, printed as nanoseconds. rospy.Time/Duration are these with `now()`."""

from __future__ import annotations

import math
from typing import Any, Self

class TVal:
    __slots__ = ("secs", "nsecs")

    def __init__(self, secs: float = 0, nsecs: int = 0) -> None:
        if isinstance(secs, float):
            if nsecs != 0:
                raise ValueError("if secs is a float, nsecs cannot be set")
            whole = math.floor(secs)
            nsecs = int(round((secs - whole) * 1e9))
            secs = whole
        total = int(secs) * 10**9 + int(nsecs)
        self.secs, self.nsecs = self._canon(total)

    def _canon(self, total: int) -> tuple[int, int]:
        return divmod(total, 10**9)

    @classmethod
    def from_sec(cls, float_secs: float) -> Self:
        return cls(float(float_secs))

    @classmethod
    def from_seconds(cls, float_secs: float) -> Self:
        return cls(float(float_secs))

    def set(self, secs: int, nsecs: int) -> None:
        self.secs, self.nsecs = self._canon(int(secs) * 10**9 + int(nsecs))

    def canon(self) -> None:
        self.set(self.secs, self.nsecs)

    def to_sec(self) -> float:
        return self.secs + self.nsecs * 1e-9

    def to_nsec(self) -> int:
        return self.secs * 10**9 + self.nsecs

    def is_zero(self) -> bool:
        return self.secs == 0 and self.nsecs == 0

    def __float__(self) -> float:
        return self.to_sec()

    def __nonzero__(self) -> bool:
        return not self.is_zero()

    __bool__ = __nonzero__

    def __eq__(self, other: Any) -> bool:
        return hasattr(other, "to_nsec") and self.to_nsec() == other.to_nsec()

    def __lt__(self, other: Any) -> bool:
        return self.to_nsec() < other.to_nsec()

    def __le__(self, other: Any) -> bool:
        return self.to_nsec() <= other.to_nsec()

    def __gt__(self, other: Any) -> bool:
        return self.to_nsec() > other.to_nsec()

    def __ge__(self, other: Any) -> bool:
        return self.to_nsec() >= other.to_nsec()

    def __hash__(self) -> int:
        return hash(self.to_nsec())

    def __repr__(self) -> str:
        return f"genpy.{type(self).__name__}[{self.to_nsec()}]"

    def __str__(self) -> str:  # genpy prints nanoseconds
        return str(self.to_nsec())

def _is_time(value: Any) -> bool:
    """A genpy Time, or a message's `time` field (builtin_interfaces/Time, with secs and nsecs)."""
    return isinstance(value, Time) or getattr(value, "_type", None) == "builtin_interfaces/Time"


def _is_duration(value: Any) -> bool:
    """A genpy Duration, or a message's `duration` field (builtin_interfaces/Duration)."""
    return isinstance(value, Duration) or getattr(value, "_type", None) == "builtin_interfaces/Duration"


class Time(TVal):
    """A point in time; never negative (genpy's ValueError)."""

    __slots__ = ()

    def _canon(self, total: int) -> tuple[int, int]:
        if total < 0:
            raise ValueError("time values must be positive")
        return divmod(total, 10**9)

    def __add__(self, other: Any) -> Time:
        if not _is_duration(other):
            return NotImplemented
        return type(self)(0, self.to_nsec() + other.to_nsec())

    __radd__ = __add__

    def __sub__(self, other: Any) -> Any:
        if _is_time(other):
            return Duration(0, self.to_nsec() - other.to_nsec())
        if _is_duration(other):
            return type(self)(0, self.to_nsec() - other.to_nsec())
        return NotImplemented

class Duration(TVal):
    """A span of time, negative or not."""

    __slots__ = ()

    def _canon(self, total: int) -> tuple[int, int]:
        secs = int(total / 10**9)  # toward zero: nsecs keeps the sign of the whole
        return secs, total - secs * 10**9

    def __add__(self, other: Any) -> Any:
        if isinstance(other, Time):
            return other + self
        if _is_duration(other):
            return type(self)(0, self.to_nsec() + other.to_nsec())
        return NotImplemented

    __radd__ = __add__

    def __sub__(self, other: Any) -> Duration:
        if not _is_duration(other):
            return NotImplemented
        return type(self)(0, self.to_nsec() - other.to_nsec())

    def __neg__(self) -> Duration:
        return type(self)(0, -self.to_nsec())

    def __abs__(self) -> Duration:
        return type(self)(0, abs(self.to_nsec()))

    def __mul__(self, k: float) -> Duration:
        return type(self)(0, int(self.to_nsec() * k))

    __rmul__ = __mul__

    def __truediv__(self, k: Any) -> Any:
        if isinstance(k, Duration):
            return self.to_nsec() / k.to_nsec()
        return type(self)(0, int(self.to_nsec() / k))

    def __floordiv__(self, k: Any) -> Any:
        if isinstance(k, Duration):
            return self.to_nsec() // k.to_nsec()
        return type(self)(0, self.to_nsec() // k)

    def __mod__(self, other: Duration) -> Duration:
        return type(self)(0, self.to_nsec() % other.to_nsec())
