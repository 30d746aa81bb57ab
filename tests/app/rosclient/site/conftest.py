"""The client libraries of app/rosclient/site imported in this process, as a program imports them
(the site folder on sys.path, the interface finder installed); everything they changed undone after."""

import sys

import pytest

from app.rosclient import boot, process

GENERATED = ("std_msgs", "example_interfaces", "rcl_interfaces", "builtin_interfaces", "geometry_msgs", "tf2_msgs", "sensor_msgs",
             "action_msgs", "unique_identifier_msgs")  # fmt: skip


@pytest.fixture()
def site():
    saved_path, saved_meta = list(sys.path), list(sys.meta_path)
    saved_hooks = list(process._shutdown_hooks)
    sys.path.insert(0, str(boot.SITE))
    process.ensure_interfaces()
    try:
        yield
    finally:
        process._connection.clear()
        process.shutdown_event.clear()
        process.shutdown_reason.clear()
        process._shutdown_hooks[:] = saved_hooks
        sys.path[:] = saved_path
        sys.meta_path[:] = saved_meta
        for name in [n for n in sys.modules if n.split(".")[0] in ("rclpy", "tf2_ros", "tf", "sensor_msgs_py", *GENERATED)]:
            del sys.modules[name]
