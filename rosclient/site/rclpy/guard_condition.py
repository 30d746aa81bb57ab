"""rclpy.guard_condition.GuardCondition: an entity a program triggers by hand (from any thread); its
callback runs once per trigger seen, inside spin."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rclpy import context as _context
from rclpy._entity import Call, Entity
from rclpy.callback_groups import CallbackGroup


class GuardCondition(Entity):
    def __init__(self, callback: Callable[[], Any] | None, callback_group: CallbackGroup, context: Any = None,
                 **_: Any) -> None:
        self.callback = callback
        self.callback_group = callback_group
        callback_group.add_entity(self)
        self._triggered = False

    def trigger(self) -> None:
        with _context.CONDITION:
            self._triggered = True
        _context.wake()

    def _is_ready(self) -> bool:
        return self._triggered

    def _take(self) -> Call | None:
        with _context.CONDITION:
            if not self._triggered:
                return None
            self._triggered = False
        callback = self.callback
        return callback if callback is not None else (lambda: None)

    def destroy(self) -> None:
        self._triggered = False
