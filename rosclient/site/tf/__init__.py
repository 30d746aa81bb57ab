"""tf (ROS 1) over tf2_ros, as rospy programs use it: `tf.TransformBroadcaster().sendTransform(
translation, rotation, time, child, parent)`, `tf.TransformListener()` with `lookupTransform(target,
source, time) -> (translation, rotation)`, `waitForTransform`, `canTransform`, `frameExists`, and
`tf.transformations` (tf/transformations.py)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from tf import transformations
from tf2_ros import Buffer, TransformBroadcaster as _Broadcaster, TransformListener as _Listener
from tf2_ros.buffer import ConnectivityException, ExtrapolationException, LookupException, TransformException

Exception = TransformException  # noqa: A001 - tf's name: `except tf.Exception`

__all__ = ["ConnectivityException", "Exception", "ExtrapolationException", "LookupException",
           "TransformBroadcaster", "TransformListener", "transformations"]


def _stamped(translation: Sequence[float], rotation: Sequence[float], time: Any, child: str, parent: str) -> Any:
    from geometry_msgs.msg import TransformStamped

    stamp = {"sec": int(getattr(time, "secs", 0) or 0), "nanosec": int(getattr(time, "nsecs", 0) or 0)}
    x, y, z = (float(v) for v in translation)
    qx, qy, qz, qw = (float(v) for v in rotation)
    return TransformStamped.from_json(
        {
            "header": {"frame_id": parent, "stamp": stamp},
            "child_frame_id": child,
            "transform": {"translation": {"x": x, "y": y, "z": z}, "rotation": {"x": qx, "y": qy, "z": qz, "w": qw}},
        }
    )


class TransformBroadcaster:
    def __init__(self, queue_size: int = 100) -> None:
        self._broadcaster = _Broadcaster()

    def sendTransform(self, translation: Sequence[float], rotation: Sequence[float], time: Any, child: str,  # noqa: N802 - tf's name
                      parent: str) -> None:
        self._broadcaster.sendTransform(_stamped(translation, rotation, time, child, parent))

    def sendTransformMessage(self, transform: Any) -> None:  # noqa: N802 - tf's name
        self._broadcaster.sendTransform(transform)


class TransformListener:
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self._buffer = Buffer()
        self._listener = _Listener(self._buffer)

    def lookupTransform(self, target_frame: str, source_frame: str, time: Any) -> tuple[list[float], list[float]]:  # noqa: N802 - tf's name
        transform = self._buffer.lookup_transform(target_frame, source_frame, time)
        t, r = transform.transform.translation, transform.transform.rotation
        return [t.x, t.y, t.z], [r.x, r.y, r.z, r.w]

    def waitForTransform(self, target_frame: str, source_frame: str, time: Any, timeout: Any,  # noqa: N802 - tf's name
                         polling_sleep_duration: Any = None) -> None:
        found, reason = self._buffer.can_transform(target_frame, source_frame, time, timeout, return_debug_tuple=True)
        if not found:
            raise TransformException(reason)

    def canTransform(self, target_frame: str, source_frame: str, time: Any) -> bool:  # noqa: N802 - tf's name
        return bool(self._buffer.can_transform(target_frame, source_frame, time))

    def frameExists(self, frame_id: str) -> bool:  # noqa: N802 - tf's name
        return self._buffer._known(frame_id.strip("/"))

    def getFrameStrings(self) -> list[str]:  # noqa: N802 - tf's name
        return sorted(self._buffer._frames)

    def getLatestCommonTime(self, source_frame: str, target_frame: str) -> Any:  # noqa: N802 - tf's name
        import rospy

        return rospy.Time(0)

    def asMatrix(self, target_frame: str, header: Any) -> Any:  # noqa: N802 - tf's name
        translation, rotation = self.lookupTransform(target_frame, header.frame_id, header.stamp)
        return transformations.concatenate_matrices(transformations.translation_matrix(translation),
                                                    transformations.quaternion_matrix(rotation))



def __getattr__(name: str) -> Any:
    if name == "msg":  # tf/tfMessage, made from its definition by the interface finder (rosclient/interfaces.py)
        import importlib

        return importlib.import_module("tf.msg")
    raise AttributeError(f"module 'tf' has no attribute '{name}'")
