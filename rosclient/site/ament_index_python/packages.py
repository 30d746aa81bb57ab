"""ament_index_python.packages: a package's folder in the workspace that `hri-lab` found
(rosclient/executables.py's search: --workspace, the workspace above, $ROS_PACKAGE_PATH, ~/*_ws)."""

from __future__ import annotations

import os
from pathlib import Path


class PackageNotFoundError(KeyError):
    pass


def _folder(package_name: str) -> Path:
    from rosclient import executables

    found = executables.find_package(package_name, executables.workspaces(Path.cwd()))
    if found is None:
        raise PackageNotFoundError(f"package '{package_name}' not found, searching: {os.getcwd()} and the workspaces")
    return found[0]


def get_package_share_directory(package_name: str, print_warning: bool = True) -> str:
    return str(_folder(package_name))


def get_package_prefix(package_name: str) -> str:
    return str(_folder(package_name))


def get_packages_with_prefixes() -> dict[str, str]:
    from rosclient import executables, packages

    found: dict[str, str] = {}
    for root in executables.workspaces(Path.cwd()):
        for name, folder in packages.find(root).items():
            found.setdefault(name, str(folder))
    return found
