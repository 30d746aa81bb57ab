"""What `hri-lab topic hz` and `topic bw` print, as ros2topic's hz and bw verbs compute it: a window
of arrival times (s, the command's monotonic clock) and message sizes, printed once a second."""

from __future__ import annotations

import math
from collections import deque

HZ_WINDOW = 10000  # messages (ros2 topic hz's default window)
BW_WINDOW = 100  # messages (ros2 topic bw's default window)


class Rate:
    """ros2 topic hz: the intervals between the arrivals of the last `window` messages."""

    def __init__(self, window: int = HZ_WINDOW) -> None:
        self.intervals: deque[float] = deque(maxlen=window)  # s
        self.last: float | None = None  # s, the newest arrival
        self.printed: float | None = None  # s, the newest arrival when it last printed

    def arrived(self, at_s: float) -> None:
        if self.last is not None:
            self.intervals.append(at_s - self.last)
        self.last = at_s

    def report(self) -> str | None:
        """Its lines, or None before two messages or when none came since it last printed."""
        if not self.intervals or self.last == self.printed:
            return None
        self.printed = self.last
        n = len(self.intervals)
        mean = sum(self.intervals) / n
        rate = 1.0 / mean if mean > 0 else 0.0
        std_dev = math.sqrt(sum((x - mean) ** 2 for x in self.intervals) / n)
        return (
            f"average rate: {rate:.3f}\n\tmin: {min(self.intervals):.3f}s max: {max(self.intervals):.3f}s "
            f"std dev: {std_dev:.5f}s window: {n}"
        )


class Bandwidth:
    """ros2 topic bw: the sizes (bytes) and arrival times (s) of the last `window` messages."""

    def __init__(self, window: int = BW_WINDOW) -> None:
        self.arrivals: deque[tuple[float, int]] = deque(maxlen=window)

    def arrived(self, at_s: float, size: int) -> None:
        self.arrivals.append((at_s, size))

    def report(self, now_s: float) -> str | None:
        """Its lines, or None before two messages."""
        if len(self.arrivals) < 2 or now_s <= self.arrivals[0][0]:
            return None
        sizes = [size for _, size in self.arrivals]
        per_s = sum(sizes) / (now_s - self.arrivals[0][0])
        show = _unit(per_s)
        mean = sum(sizes) / len(sizes)
        return (
            f"{show(per_s)}/s from {len(sizes)} messages\n"
            f"\tMessage size mean: {show(mean)} min: {show(min(sizes))} max: {show(max(sizes))}"
        )


def _unit(bytes_per_s: float):
    """ros2 topic bw's unit, chosen by the rate: B, KB or MB (of 1000)."""
    if bytes_per_s < 1000:
        return lambda n: f"{n:.0f} B"
    if bytes_per_s < 1_000_000:
        return lambda n: f"{n / 1000:.2f} KB"
    return lambda n: f"{n / 1000 / 1000:.2f} MB"
