"""rclpy.utilities: the default context's state, the program's arguments without `--ros-args`, and
what rclpy says of its middleware (here: the lab's rosbridge endpoint)."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from rosclient import process
from rclpy.context import Context, default_context

RMW = "rmw_rosbridge_hri_lab"  # what get_rmw_implementation_identifier() names: rosbridge to the lab


def get_default_context(*, shutting_down: bool = False) -> Context:
    return default_context()


def remove_ros_args(args: Sequence[str] | None = None) -> list[str]:
    return process.program_args(list(sys.argv if args is None else args))[0]


def ok(*, context: Context | None = None) -> bool:
    return (context or default_context()).ok()


def shutdown(*, context: Context | None = None) -> None:
    (context or default_context()).shutdown()


def try_shutdown(*, context: Context | None = None) -> None:
    (context or default_context()).try_shutdown()


def get_rmw_implementation_identifier() -> str:
    return RMW


def get_available_rmw_implementations() -> set[str]:
    return {RMW}


def timeout_sec_to_nsec(timeout_sec: float | None) -> int:
    """rclpy's rule: None or negative waits forever (-1), else nanoseconds."""
    if timeout_sec is None or timeout_sec < 0:
        return -1
    return int(float(timeout_sec) * 1e9)
