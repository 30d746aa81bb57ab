"""The core of the `launch` vocabulary `hri-lab launch` reads Python launch files with (the classes
of ROS 2's launch package that generate_launch_description() builds): entities, substitutions, the
context they are performed in, conditions. What a launch file describes is done by the runner that
rosclient/pylaunch.py puts in the context (`context.runner`): it starts processes, runs timers,
emits events and finds packages. Written from launch's documented behaviour, not its code."""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


class LaunchError(Exception):
    """A launch description that cannot be carried out (names what and why)."""


class SubstitutionFailure(LaunchError):
    pass


class InvalidLaunchFileError(LaunchError):
    pass


class Unsupported(ImportError):
    """A part of launch / launch_ros that hri-lab launch does not have, refused by name."""


def refuse(module: str, name: str, supported: Iterable[str]) -> Unsupported:
    return Unsupported(
        f"hri-lab launch does not support {module}.{name} (what it has of {module}: {', '.join(sorted(supported))})",
        name=name,
    )


class LaunchContext:
    """What performing a description reads and changes: launch configurations (the launch
    arguments, and launch_ros's namespace, global parameters and remaps), the environment
    processes get, the locals an event handler's actions see, the file being read."""

    def __init__(self, runner: Any = None, argv: list[str] | None = None) -> None:
        self.runner = runner
        self.argv = list(argv or [])
        self.launch_configurations: dict[str, Any] = {}
        self.environment: dict[str, str] = dict(os.environ)
        self.locals = _Locals()
        self.files: list[Path] = []  # the launch files being read, innermost last
        self._stack: list[tuple[dict[str, Any], dict[str, str]]] = []
        self.is_shutdown = False

    def push(self) -> None:
        self._stack.append((dict(self.launch_configurations), dict(self.environment)))

    def pop(self) -> None:
        if self._stack:
            self.launch_configurations, self.environment = self._stack.pop()

    def snapshot(self) -> tuple[dict[str, Any], dict[str, str], list[Path]]:
        return dict(self.launch_configurations), dict(self.environment), list(self.files)

    def restore(self, snap: tuple[dict[str, Any], dict[str, str], list[Path]]) -> None:
        self.launch_configurations, self.environment, self.files = dict(snap[0]), dict(snap[1]), list(snap[2])

    def extend_locals(self, values: dict[str, Any]) -> None:
        for key, value in values.items():
            setattr(self.locals, key, value)

    def perform_substitution(self, substitution: Substitution) -> str:
        return substitution.perform(self)


class _Locals:
    pass


# --- entities ------------------------------------------------------------------------------------------
class LaunchDescriptionEntity:
    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None

    def describe_sub_entities(self) -> list[LaunchDescriptionEntity]:
        return []

    def declared_arguments(self) -> list[Any]:
        """The DeclareLaunchArgument actions this entity holds, for `get_launch_arguments`: none
        here; a DeclareLaunchArgument itself, and what a group or a description holds (not what an
        include will bring: it is read only when it runs)."""
        return []


class Condition:
    def __init__(self, predicate: Any = None) -> None:
        self._predicate = predicate

    def evaluate(self, context: LaunchContext) -> bool:
        return bool(self._predicate(context)) if self._predicate else True


class Action(LaunchDescriptionEntity):
    """An entity that does something when visited; skipped when its condition is false."""

    def __init__(self, *, condition: Condition | None = None) -> None:
        self.condition = condition

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        if self.condition is not None and not self.condition.evaluate(context):
            return None
        return self.execute(context)

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None


class LaunchDescription(LaunchDescriptionEntity):
    def __init__(self, initial_entities: Iterable[LaunchDescriptionEntity] | None = None, *, deprecated_reason=None):
        self.entities: list[LaunchDescriptionEntity] = list(initial_entities or [])
        self.deprecated = deprecated_reason is not None

    def add_action(self, action: LaunchDescriptionEntity) -> None:
        self.entities.append(action)

    def add_entity(self, entity: LaunchDescriptionEntity) -> None:
        self.entities.append(entity)

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return list(self.entities)

    def describe_sub_entities(self) -> list[LaunchDescriptionEntity]:
        return list(self.entities)

    def declared_arguments(self) -> list[Any]:
        return [argument for entity in self.entities for argument in entity.declared_arguments()]

    def get_launch_arguments(self, conditional_inclusion: bool = False) -> list[Any]:
        return self.declared_arguments()


# --- substitutions -----------------------------------------------------------------------------------------
class Substitution:
    def perform(self, context: LaunchContext) -> str:
        raise NotImplementedError

    def describe(self) -> str:
        return type(self).__name__

    def __add__(self, other: Any) -> list[Any]:  # `LaunchConfiguration('x') + '.yaml'` as a list of parts
        return [self, other]

    def __radd__(self, other: Any) -> list[Any]:
        return [other, self]


SomeSubstitutionsType = Any


def normalize(value: Any) -> list[Any]:
    """A str, a Substitution or an iterable of them as a list of parts."""
    if value is None:
        return []
    if isinstance(value, str | Substitution):
        return [value]
    if isinstance(value, int | float | bool):
        return [str(value)]
    if isinstance(value, Path):
        return [str(value)]
    out: list[Any] = []
    for part in value:
        out.extend(normalize(part))
    return out


def perform(context: LaunchContext, value: Any) -> str:
    """The text of a str, a Substitution, or a list of them joined."""
    return "".join(p if isinstance(p, str) else p.perform(context) for p in normalize(value))


def perform_substitutions(context: LaunchContext, subs: Any) -> str:
    return perform(context, subs)


def is_substitution(value: Any) -> bool:
    return isinstance(value, Substitution) or (
        isinstance(value, list | tuple) and bool(value) and all(isinstance(v, str | Substitution) for v in value)
    )


@dataclass
class ProcessPlan:
    """A process an action asks the runner to start: a node (a package's executable, run as
    `hri-lab run` runs it) or a command line."""

    action: Any
    label: str  # its name in the launch log: `[talker-1]`
    argv: list[str] = field(default_factory=list)  # a command (ExecuteProcess)
    program: Path | None = None  # a node's program file
    entry: str | None = None  # a node's console_scripts entry point
    args: list[str] = field(default_factory=list)  # a node's arguments (its --ros-args included)
    env: dict[str, str] = field(default_factory=dict)
    cwd: str | None = None
    output: str = "log"
    shell: bool = False
    workspace: Path | None = None
    sigterm_timeout: float = 5.0
    respawn: bool = False
    respawn_delay: float = 0.0
