"""The `launch_ros` package of ROS 2 as `hri-lab launch` provides it: Node, namespaces, global
parameters and remaps, FindPackageShare; what is not here is refused by name when imported."""

from __future__ import annotations

from typing import Any

from launch._core import refuse
from launch_ros import actions, parameter_descriptions, substitutions

__all__ = ["actions", "parameter_descriptions", "substitutions"]


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch_ros", name, __all__)
