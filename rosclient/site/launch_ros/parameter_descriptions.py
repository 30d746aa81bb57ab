"""launch_ros.parameter_descriptions: a parameter's value with its type, a parameter file."""

from __future__ import annotations

from typing import Any

from launch._core import refuse

__all__ = ["Parameter", "ParameterFile", "ParameterValue"]


class ParameterValue:
    def __init__(self, value: Any, *, value_type: Any = None) -> None:
        self.value, self.value_type = value, value_type


class ParameterFile:
    def __init__(self, param_file: Any, *, allow_substs: Any = False) -> None:
        self.param_file, self.allow_substs = param_file, allow_substs


class Parameter:
    def __init__(self, name: Any, value: Any, *, value_type: Any = None) -> None:
        self.name, self.value, self.value_type = name, value, value_type


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch_ros.parameter_descriptions", name, __all__)
