"""rclpy.waitable.Waitable: an entity that is more than one of the wait set's kinds (an action server
or client): it says when it is ready and what taking from it runs (rclpy/_entity.py)."""

from __future__ import annotations

from typing import Any

from rclpy._entity import Entity
from rclpy.callback_groups import CallbackGroup


class NumberOfEntities:
    """rclpy's count of a waitable's parts (kept for programs that build waitables' counts)."""

    def __init__(self, num_subs: int = 0, num_gcs: int = 0, num_timers: int = 0, num_clients: int = 0,
                 num_services: int = 0, num_events: int = 0) -> None:
        self.num_subscriptions, self.num_guard_conditions, self.num_timers = num_subs, num_gcs, num_timers
        self.num_clients, self.num_services, self.num_events = num_clients, num_services, num_events


class Waitable(Entity):
    def __init__(self, callback_group: CallbackGroup) -> None:
        self.callback_group = callback_group
        self.callback_group.add_entity(self)
        self._futures: list[Any] = []

    def add_future(self, future: Any) -> None:
        self._futures.append(future)

    def remove_future(self, future: Any) -> None:
        if future in self._futures:
            self._futures.remove(future)

    def destroy(self) -> None:
        pass
