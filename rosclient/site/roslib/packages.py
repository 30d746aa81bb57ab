"""roslib.packages: a package's folder, found as `hri-lab run` finds packages (rosclient/executables.py)."""

from __future__ import annotations

from pathlib import Path


class InvalidROSPkgException(Exception):
    pass


def get_pkg_dir(package: str, required: bool = True, ros_root: str | None = None) -> str:
    from rosclient import executables

    found = executables.find_package(package, executables.workspaces(Path.cwd()))
    if found is None:
        raise InvalidROSPkgException(f"Cannot locate installation of package {package}: [rospack] Error: package "
                                     f"'{package}' not found")
    return str(found[0])
