"""ament_index_python as a launch file uses it: a package's share folder is its folder in the
workspace's sources (where package.xml, launch/ and config/ are before colcon installs them)."""

from __future__ import annotations

from ament_index_python.packages import PackageNotFoundError, get_package_prefix, get_package_share_directory

__all__ = ["PackageNotFoundError", "get_package_prefix", "get_package_share_directory"]
