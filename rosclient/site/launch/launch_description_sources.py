"""launch.launch_description_sources: another launch file (Python, XML or YAML) to include."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from launch._core import InvalidLaunchFileError, LaunchContext, perform, refuse

__all__ = [
    "AnyLaunchDescriptionSource",
    "FrontendLaunchDescriptionSource",
    "LaunchDescriptionSource",
    "PythonLaunchDescriptionSource",
    "XMLLaunchDescriptionSource",
    "YAMLLaunchDescriptionSource",
]


class LaunchDescriptionSource:
    kind = "any"

    def __init__(self, launch_file_path: Any) -> None:
        self.location = launch_file_path

    def path(self, context: LaunchContext) -> Path:
        return Path(perform(context, self.location))

    def get_launch_description(self, context: LaunchContext) -> Any:
        path = self.path(context)
        if not path.is_file():
            raise InvalidLaunchFileError(f"launch file {path} does not exist")
        return context.runner.load(path, self.kind, context)


class PythonLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "python"


class AnyLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "any"


class FrontendLaunchDescriptionSource(LaunchDescriptionSource):
    kind = "frontend"


class XMLLaunchDescriptionSource(FrontendLaunchDescriptionSource):
    kind = "xml"


class YAMLLaunchDescriptionSource(FrontendLaunchDescriptionSource):
    kind = "yaml"


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.launch_description_sources", name, __all__)
