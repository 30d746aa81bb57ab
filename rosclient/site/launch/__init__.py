"""The `launch` package of ROS 2 as `hri-lab launch` provides it to Python launch files
(rosclient/pylaunch.py runs them): generate_launch_description()'s vocabulary; what is not
here is refused by name when imported."""

from __future__ import annotations

from typing import Any

from launch import actions, conditions, event_handlers, events, launch_description_sources, substitutions
from launch._core import (
    Action,
    Condition,
    InvalidLaunchFileError,
    LaunchContext,
    LaunchDescription,
    LaunchDescriptionEntity,
    SomeSubstitutionsType,
    Substitution,
    SubstitutionFailure,
    refuse,
)
from launch.event_handlers import EventHandler
from launch.event import Event
from launch.launch_description_sources import LaunchDescriptionSource

__all__ = [
    "Action",
    "Condition",
    "Event",
    "EventHandler",
    "InvalidLaunchFileError",
    "LaunchContext",
    "LaunchDescription",
    "LaunchDescriptionEntity",
    "LaunchDescriptionSource",
    "SomeSubstitutionsType",
    "Substitution",
    "SubstitutionFailure",
    "actions",
    "conditions",
    "event_handlers",
    "events",
    "launch_description_sources",
    "substitutions",
]


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch", name, __all__)
