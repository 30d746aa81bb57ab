"""rclpy.lifecycle.managed_entity: what a lifecycle node activates and deactivates with itself."""

from __future__ import annotations

from enum import IntEnum
from typing import Any


class TransitionCallbackReturn(IntEnum):
    """What a transition's callback returns (lifecycle_msgs/Transition's TRANSITION_CALLBACK_*);
    here, where the entities' default callbacks return it, as rclpy's managed_entity has it too."""

    SUCCESS = 97
    FAILURE = 98
    ERROR = 99


class ManagedEntity:
    def on_configure(self, state: Any) -> TransitionCallbackReturn:
        return TransitionCallbackReturn.SUCCESS

    on_cleanup = on_shutdown = on_activate = on_deactivate = on_error = on_configure


class SimpleManagedEntity(ManagedEntity):
    """Enabled while the node is active."""

    def __init__(self) -> None:
        self._enabled = False

    def on_activate(self, state: Any) -> Any:
        self._enabled = True
        return super().on_activate(state)

    def on_deactivate(self, state: Any) -> Any:
        self._enabled = False
        return super().on_deactivate(state)

    @property
    def is_activated(self) -> bool:
        return self._enabled
