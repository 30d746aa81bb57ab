"""launch.event_handlers: actions done when a process starts or exits, or the launch shuts down."""

from __future__ import annotations

from typing import Any

from launch._core import LaunchContext, refuse
from launch.events import Shutdown
from launch.events.process import ProcessExited, ProcessStarted

__all__ = ["EventHandler", "OnProcessExit", "OnProcessStart", "OnShutdown"]


class EventHandler:
    """Matches an event; its entities are done with `event` among the context's locals."""

    def __init__(self, *, matcher: Any, entities: Any = None, handle_once: bool = False) -> None:
        self.matcher = matcher
        self.entities = entities
        self.handle_once = handle_once

    def matches(self, event: Any) -> bool:
        return bool(self.matcher(event))

    def handle(self, event: Any, context: LaunchContext) -> list[Any]:
        context.extend_locals({"event": event})
        return _entities(self.entities, event, context)


def _entities(given: Any, event: Any, context: LaunchContext) -> list[Any]:
    if given is None:
        return []
    if callable(given) and not hasattr(given, "visit"):
        given = given(event, context)
        if given is None:
            return []
    if hasattr(given, "visit"):
        return [given]
    return list(given)


class _OnProcess(EventHandler):
    kind: Any = ProcessStarted

    def __init__(self, *, target_action: Any = None, entities: Any = None, handle_once: bool = False) -> None:
        def matcher(event: Any) -> bool:
            if not isinstance(event, self.kind):
                return False
            if target_action is None:
                return True
            if callable(target_action) and not hasattr(target_action, "visit"):
                return bool(target_action(event.action))
            return event.action is target_action

        super().__init__(matcher=matcher, entities=entities, handle_once=handle_once)
        self.target_action = target_action


class OnProcessStart(_OnProcess):
    kind = ProcessStarted

    def __init__(self, *, target_action: Any = None, on_start: Any = None, handle_once: bool = False) -> None:
        super().__init__(target_action=target_action, entities=on_start, handle_once=handle_once)


class OnProcessExit(_OnProcess):
    kind = ProcessExited

    def __init__(self, *, target_action: Any = None, on_exit: Any = None, handle_once: bool = False) -> None:
        super().__init__(target_action=target_action, entities=on_exit, handle_once=handle_once)


class OnShutdown(EventHandler):
    def __init__(self, *, on_shutdown: Any = None, handle_once: bool = False) -> None:
        super().__init__(matcher=lambda event: isinstance(event, Shutdown), entities=on_shutdown)


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.event_handlers", name, __all__)
