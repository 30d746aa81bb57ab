"""launch.events.process: a process started, exited."""

from __future__ import annotations

from typing import Any

from launch._core import refuse
from launch.event import Event

__all__ = ["ProcessExited", "ProcessStarted", "RunningProcessEvent", "ShutdownProcess", "SignalProcess"]


class RunningProcessEvent(Event):
    def __init__(self, *, action: Any, name: str, cmd: list[str], cwd: str | None, env: Any, pid: int) -> None:
        self.action, self.name, self.cmd, self.cwd, self.env, self.pid = action, name, cmd, cwd, env, pid

    @property
    def execute_process_action(self) -> Any:
        return self.action


class ProcessStarted(RunningProcessEvent):
    name = "launch.events.process.ProcessStarted"


class ProcessExited(RunningProcessEvent):
    name = "launch.events.process.ProcessExited"

    def __init__(self, *, returncode: int, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.returncode = returncode


class ShutdownProcess(Event):
    """Asks for one process (or those a matcher picks) to be stopped."""

    name = "launch.events.process.ShutdownProcess"

    def __init__(self, *, process_matcher: Any) -> None:
        self.process_matcher = process_matcher


class SignalProcess(ShutdownProcess):
    name = "launch.events.process.SignalProcess"

    def __init__(self, *, signal_number: int, process_matcher: Any) -> None:
        super().__init__(process_matcher=process_matcher)
        self.signal_number = signal_number


def matches_action(target_action: Any) -> Any:
    return lambda action: action is target_action


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.events.process", name, __all__)
