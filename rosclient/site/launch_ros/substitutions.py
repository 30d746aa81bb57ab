"""launch_ros.substitutions: a package's folders (its sources', as nothing is installed here)."""

from __future__ import annotations

from typing import Any

from launch._core import LaunchContext, Substitution, SubstitutionFailure, normalize, perform, refuse

__all__ = ["ExecutableInPackage", "FindPackage", "FindPackagePrefix", "FindPackageShare"]


class FindPackageShare(Substitution):
    def __init__(self, package: Any) -> None:
        self.package = normalize(package)

    def perform(self, context: LaunchContext) -> str:
        return str(context.runner.package_dir(perform(context, self.package)))

    def find(self, package_name: str) -> str:
        from ament_index_python.packages import get_package_share_directory

        return get_package_share_directory(package_name)

    def __truediv__(self, other: Any) -> Any:
        from launch.substitutions import PathJoinSubstitution

        return PathJoinSubstitution([self, other])


FindPackagePrefix = FindPackage = FindPackageShare


class ExecutableInPackage(Substitution):
    def __init__(self, executable: Any, package: Any) -> None:
        self.executable, self.package = normalize(executable), normalize(package)

    def perform(self, context: LaunchContext) -> str:
        """The executable's installed file (Runner.installed): a console_scripts entry point or a
        script, either started by ExecuteProcess as `ros2 run`/`rosrun` would start it."""
        found = context.runner.executable(perform(context, self.package), perform(context, self.executable))
        return str(context.runner.installed(found))


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch_ros.substitutions", name, __all__)
