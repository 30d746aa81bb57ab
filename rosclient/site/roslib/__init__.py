"""roslib (ROS 1) as rospy scripts open with it: `import roslib; roslib.load_manifest('pkg')` (a
no-op, as under catkin, where the package's Python path is set up already), roslib.message's
get_message_class / get_service_class, roslib.packages.get_pkg_dir."""

from __future__ import annotations

from roslib import message, packages

__all__ = ["load_manifest", "message", "packages"]


def load_manifest(package_name: str, bootstrap_version: str = "0.7") -> None:
    """Nothing to do: catkin (and hri-lab run) already put the package's modules on the path."""
    return None
