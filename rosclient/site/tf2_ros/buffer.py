"""tf2_ros.Buffer: the newest transform of every frame (from a TransformListener, or set by hand)
and lookups through the tree: `lookup_transform(target, source, time)` is the source frame's pose in
the target frame (what turns data in `source` into `target`), chained through their common
ancestor. Time is the newest of each transform (`Time()`/`rospy.Time(0)`, what programs ask for);
`timeout` waits for the frames to arrive. rclpy's and rospy's spellings both work
(`lookup_transform`, `can_transform`; ROS 1's `lookup_transform(target, source, time, timeout)`).
rclpy's waits without blocking are there as tf2_ros has them: `wait_for_transform_async` (an
rclpy Future whose result is the transform once it can be looked up, completed by the listener's
thread as new transforms arrive) and `await buffer.lookup_transform_async(...)`.
"""

from __future__ import annotations

import threading
import time as _time
from typing import Any

import numpy as np

from rosclient import process
from tf2_ros._transforms import compose, decompose


class TransformException(Exception):
    pass


class LookupException(TransformException):
    pass


class ConnectivityException(TransformException):
    pass


class ExtrapolationException(TransformException):
    pass


class InvalidArgumentException(TransformException):
    pass


class TimeoutException(TransformException):
    pass


def seconds(timeout: Any) -> float:
    """A timeout given as rclpy's Duration, rospy's Duration or a number, in seconds."""
    if timeout is None:
        return 0.0
    if hasattr(timeout, "nanoseconds"):
        return float(timeout.nanoseconds) / 1e9
    if hasattr(timeout, "to_sec"):
        return float(timeout.to_sec())
    return float(timeout)


class Buffer:
    def __init__(self, cache_time: Any = None, node: Any = None, debug: bool = True, **_: Any) -> None:
        self._frames: dict[str, tuple[str, np.ndarray, dict]] = {}  # child -> (parent, 4x4, stamp JSON)
        self._changed = threading.Condition()
        self._new_data_callbacks: list[Any] = []  # called (without the lock) after each new transform

    # --- filling ----------------------------------------------------------------------------------
    def set_transform(self, transform: Any, authority: str = "") -> bool:
        return self._set_json(transform.to_json() if hasattr(transform, "to_json") else transform)

    def set_transform_static(self, transform: Any, authority: str = "") -> bool:
        return self.set_transform(transform, authority)

    def _set_json(self, item: dict) -> bool:
        parent = str(item.get("header", {}).get("frame_id", "")).strip("/")
        child = str(item.get("child_frame_id", "")).strip("/")
        if not parent or not child or parent == child:
            return False
        t, r = item.get("transform", {}).get("translation", {}), item.get("transform", {}).get("rotation", {})
        matrix = compose([t.get(a, 0.0) for a in "xyz"], [r.get(a, 1.0 if a == "w" else 0.0) for a in "xyzw"])
        with self._changed:
            self._frames[child] = (parent, matrix, item.get("header", {}).get("stamp", {}))
            self._changed.notify_all()
            callbacks = list(self._new_data_callbacks)
        for callback in callbacks:
            callback()
        return True

    def _offer_message(self, message: dict) -> None:
        """A tf2_msgs/TFMessage from /tf or /tf_static (the listener's handler)."""
        for item in message.get("transforms", []) if isinstance(message, dict) else []:
            if isinstance(item, dict):
                self._set_json(item)

    def clear(self) -> None:
        with self._changed:
            self._frames.clear()

    # --- lookups ----------------------------------------------------------------------------------
    def _root_pose(self, frame: str) -> tuple[str, np.ndarray]:
        """The frame's root and its pose in the root (called with the lock held)."""
        pose, seen = np.eye(4), {frame}
        while frame in self._frames:
            parent, matrix, _ = self._frames[frame]
            pose = matrix @ pose
            frame = parent
            if frame in seen:
                raise ConnectivityException(f"the frames loop at {frame}")
            seen.add(frame)
        return frame, pose

    def _known(self, frame: str) -> bool:
        return frame in self._frames or any(parent == frame for parent, _, _ in self._frames.values())

    def _relative(self, target: str, source: str) -> np.ndarray:
        target, source = target.strip("/"), source.strip("/")
        for frame, argument in ((target, "target_frame"), (source, "source_frame")):
            if not self._known(frame):
                raise LookupException(f'"{frame}" passed to lookupTransform argument {argument} does not exist. ')
        target_root, target_pose = self._root_pose(target)
        source_root, source_pose = self._root_pose(source)
        if target_root != source_root:
            raise ConnectivityException(
                f"Could not find a connection between '{target}' and '{source}' because they are not part of "
                f"the same tree. Tf has two or more unconnected trees."
            )
        return np.linalg.solve(target_pose, source_pose)

    def _wait(self, target: str, source: str, timeout: Any) -> np.ndarray:
        deadline = _time.monotonic() + seconds(timeout)
        with self._changed:
            while True:
                try:
                    return self._relative(target, source)
                except TransformException:
                    left = deadline - _time.monotonic()
                    if left <= 0 or process.shutdown_event.is_set():
                        raise
                    self._changed.wait(min(left, 0.1))

    def lookup_transform(self, target_frame: str, source_frame: str, time: Any = None, timeout: Any = None) -> Any:
        from geometry_msgs.msg import TransformStamped

        relative = self._wait(target_frame, source_frame, timeout)
        (x, y, z), (qx, qy, qz, qw) = decompose(relative)
        now = _time.time()
        return TransformStamped.from_json(
            {
                "header": {"frame_id": target_frame.strip("/"), "stamp": _stamp(now)},
                "child_frame_id": source_frame.strip("/"),
                "transform": {
                    "translation": {"x": x, "y": y, "z": z},
                    "rotation": {"x": qx, "y": qy, "z": qz, "w": qw},
                },
            }
        )

    def can_transform(self, target_frame: str, source_frame: str, time: Any = None, timeout: Any = None,
                      return_debug_tuple: bool = False) -> Any:
        try:
            self._wait(target_frame, source_frame, timeout)
            found, reason = True, ""
        except TransformException as exc:
            found, reason = False, str(exc)
        return (found, reason) if return_debug_tuple else found

    def can_transform_core(self, target_frame: str, source_frame: str, time: Any = None) -> tuple[bool, str]:
        return self.can_transform(target_frame, source_frame, time, return_debug_tuple=True)

    def lookup_transform_core(self, target_frame: str, source_frame: str, time: Any = None) -> Any:
        return self.lookup_transform(target_frame, source_frame, time)

    def wait_for_transform_async(self, target_frame: str, source_frame: str, time: Any = None) -> Any:
        """An rclpy Future set to the transform once it is available (at once if it is), as
        tf2_ros's: completed from the thread that brings the transform, its done callbacks run there
        (or as tasks of the future's executor)."""
        from rclpy.task import Future

        future = Future()
        if self.can_transform_core(target_frame, source_frame, time)[0]:
            future.set_result(self.lookup_transform_core(target_frame, source_frame, time))
            return future

        def on_new_data() -> None:
            if future.done():
                return
            try:
                if self.can_transform_core(target_frame, source_frame, time)[0]:
                    future.set_result(self.lookup_transform_core(target_frame, source_frame, time))
            except BaseException as exc:  # noqa: BLE001 - the future's outcome, raised by whoever awaits it
                future.set_exception(exc)

        def forget(_: Any) -> None:
            with self._changed:
                if on_new_data in self._new_data_callbacks:
                    self._new_data_callbacks.remove(on_new_data)

        with self._changed:
            self._new_data_callbacks.append(on_new_data)
        future.add_done_callback(forget)
        on_new_data()  # a transform may have come between the first look and the registration
        return future

    async def lookup_transform_async(self, target_frame: str, source_frame: str, time: Any = None) -> Any:
        """The transform, once it is available: `await buffer.lookup_transform_async(...)` in a
        coroutine callback suspends it (not the executor) until then."""
        await self.wait_for_transform_async(target_frame, source_frame, time)
        return self.lookup_transform_core(target_frame, source_frame, time)

    def all_frames_as_string(self) -> str:
        with self._changed:
            return "".join(f"Frame {c} exists with parent {p}.\n" for c, (p, _, _) in sorted(self._frames.items()))

    def all_frames_as_yaml(self) -> str:
        with self._changed:
            return "".join(f"{c}: \n  parent: '{p}'\n" for c, (p, _, _) in sorted(self._frames.items()))


def _stamp(now: float) -> dict:
    sec = int(now)
    return {"sec": sec, "nanosec": int((now - sec) * 1e9)}
