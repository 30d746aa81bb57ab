"""tf2_ros.StaticTransformBroadcaster: /tf_static. It sends every transform it was given each time,
as tf2_ros' does; the lab keeps them while the program runs and sends them to later subscribers
(latched)."""

from __future__ import annotations

from typing import Any

from rosclient import process
from tf2_ros.transform_broadcaster import TYPE, TransformBroadcaster, _json


class StaticTransformBroadcaster(TransformBroadcaster):
    TOPIC = "/tf_static"

    def __init__(self, node: Any = None, qos: Any = None, **kwargs: Any) -> None:
        super().__init__(node, qos, **kwargs)
        self._static: dict[str, dict] = {}  # child -> its transform

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 - tf2_ros' name
        for item in _json(transform):
            self._static[item.get("child_frame_id", "")] = item
        process.publish(self.TOPIC, TYPE, {"transforms": list(self._static.values())})

    send_transform = sendTransform
