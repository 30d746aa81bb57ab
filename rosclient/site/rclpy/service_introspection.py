"""rclpy.service_introspection: a client's or a service's calls published as events, as ROS 2
(Iron and later) does: `configure_introspection(clock, qos, state)` on a Client or a Service; with
METADATA each step of a call (request sent, request received, response sent, response received)
goes to `<service>/_service_event` as `<pkg>/srv/<Name>_Event` (`info`: service_msgs/ServiceEventInfo
— the step, the clock's time, the client's 16-byte gid, the call's sequence number); with CONTENTS
the request or the response rides along (one-item sequences `request`, `response`); OFF stops it.

Over rosbridge a service does not learn its caller's gid: a service's events carry sixteen zeros in
`client_gid`, and the sequence number it counts itself (its calls in the order it received them)."""

from __future__ import annotations

import base64
import itertools
import os
from enum import IntEnum
from typing import Any

from rosclient import process

REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED = 0, 1, 2, 3  # ServiceEventInfo's steps


class ServiceIntrospectionState(IntEnum):
    OFF = 0
    METADATA = 1
    CONTENTS = 2


class Introspection:
    """What a Client or a Service publishes of its calls (OFF until configured)."""

    def __init__(self, service_name: str, srv_type: Any, gid: bytes = bytes(16)) -> None:
        self.topic = f"{service_name.rstrip('/')}/_service_event"
        self.type = f"{getattr(srv_type, '_ros2_type', '') or srv_type._type}_Event"
        self.state = ServiceIntrospectionState.OFF
        self.clock: Any = None
        self.gid = base64.b64encode(gid).decode("ascii")  # char[16]: base64 text in rosbridge's JSON
        self.sequence = itertools.count(1)

    def configure(self, clock: Any, qos: Any, state: ServiceIntrospectionState | int) -> None:
        self.clock, self.state = clock, ServiceIntrospectionState(int(state))

    def event(self, step: int, sequence: int, request: Any = None, response: Any = None) -> None:
        if self.state == ServiceIntrospectionState.OFF:
            return
        contents = self.state == ServiceIntrospectionState.CONTENTS
        sec, nanosec = divmod(self.clock.now().nanoseconds, 1_000_000_000)
        process.publish(
            self.topic,
            self.type,
            {
                "info": {
                    "event_type": step,
                    "stamp": {"sec": sec, "nanosec": nanosec},
                    "client_gid": self.gid,
                    "sequence_number": sequence,
                },
                "request": [request.to_json()] if contents and request is not None else [],
                "response": [response.to_json()] if contents and response is not None else [],
            },
        )


def client_gid() -> bytes:
    """A client's 16-byte id, as rmw gives each client its own."""
    return os.urandom(16)
