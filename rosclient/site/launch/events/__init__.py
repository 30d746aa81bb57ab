"""launch.events: what happens while a launch runs (Shutdown; launch.events.process's)."""

from __future__ import annotations

from typing import Any

from launch._core import refuse
from launch.event import Event

__all__ = ["Event", "Shutdown", "process"]


class Shutdown(Event):
    """Asks the launch to end: every process is stopped (SIGINT, then SIGTERM, then SIGKILL)."""

    name = "launch.events.Shutdown"

    def __init__(self, *, reason: str = "reason not given", due_to_sigint: bool = False) -> None:
        self.reason = reason
        self.due_to_sigint = due_to_sigint


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    if name == "process":
        import importlib

        return importlib.import_module("launch.events.process")
    raise refuse("launch.events", name, __all__)
