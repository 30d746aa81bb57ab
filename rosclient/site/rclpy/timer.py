"""rclpy.timer: Timer (ready every period, on the steady clock; late, it skips the missed periods and
keeps its phase) and Rate (`sleep()` to the next period; unlike rclpy's it needs no thread spinning)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

from rosclient import process
from rclpy import context
from rclpy._entity import Call, Entity
from rclpy.callback_groups import CallbackGroup


class Timer(Entity):
    def __init__(self, callback: Callable[..., Any] | None, callback_group: CallbackGroup, timer_period_ns: int,
                 clock: Any = None, *, autostart: bool = True, **_: Any) -> None:
        if not timer_period_ns > 0:
            raise ValueError("create_timer: timer_period_sec must be > 0")
        self.callback = callback
        self.callback_group = callback_group
        callback_group.add_entity(self)
        self.timer_period_ns = int(timer_period_ns)
        self.clock = clock
        self._canceled = not autostart
        self._next = time.monotonic() + self.timer_period_ns / 1e9

    def _due(self) -> float | None:
        return None if self._canceled else self._next

    def _is_ready(self) -> bool:
        return not self._canceled and time.monotonic() >= self._next

    def _take(self) -> Call | None:
        with context.CONDITION:
            if not self._is_ready():
                return None
            period = self.timer_period_ns / 1e9
            now = time.monotonic()
            self._next += period
            if self._next < now:  # late: skip the missed periods, keep the phase
                self._next += math.ceil((now - self._next) / period) * period
        callback = self.callback
        return callback if callback is not None else (lambda: None)

    def cancel(self) -> None:
        self._canceled = True

    def is_canceled(self) -> bool:
        return self._canceled

    def reset(self) -> None:
        with context.CONDITION:
            self._canceled = False
            self._next = time.monotonic() + self.timer_period_ns / 1e9
        context.wake()

    def is_ready(self) -> bool:
        return self._is_ready()

    def time_since_last_call(self) -> int:
        return int(max(0.0, time.monotonic() - (self._next - self.timer_period_ns / 1e9)) * 1e9)

    def time_until_next_call(self) -> int | None:
        return None if self._canceled else int(max(self._next - time.monotonic(), 0.0) * 1e9)

    def destroy(self) -> None:
        self.cancel()


class Rate:
    def __init__(self, frequency: float, clock: Any = None) -> None:
        if not frequency > 0:
            raise ValueError("create_rate: frequency must be > 0")
        self.period = 1.0 / frequency
        self.next = time.monotonic() + self.period

    def sleep(self) -> None:
        wait = self.next - time.monotonic()
        if wait > 0:
            process.shutdown_event.wait(wait)
        self.next = max(self.next + self.period, time.monotonic())

    def destroy(self) -> None:
        pass
