"""rclpy imported as a program imports it (the site fixture), initialised over a RecordingConnection
that stands for the lab's: what the program sends is kept, what the lab sends is fed to the handlers."""

from __future__ import annotations

from concurrent.futures import Future as WireFuture

import pytest

from app.rosclient import process


class RecordingConnection:
    """The lab's side of the program's connection: ops sent are recorded; a service advertised is
    taken (no refusal); a call's wire future is left for the test to answer."""

    def __init__(self) -> None:
        self.sent: list[dict] = []
        self.topic_handlers: dict[str, list] = {}
        self.service_handlers: dict[str, object] = {}
        self.calls: list[WireFuture] = []

    def send(self, message: dict) -> None:
        self.sent.append(message)

    def subscribe(self, topic, type_name, handler, queue_length=0, throttle_rate=0) -> str:
        self.topic_handlers.setdefault(topic, []).append(handler)
        return f"subscribe:{topic}"

    def unsubscribe(self, topic, sid, handler) -> None:
        self.topic_handlers[topic].remove(handler)

    def advertise_service(self, name, type_name, handler, definition=None, check=False) -> str | None:
        self.service_handlers[name] = handler
        return None

    def service_response(self, call_id, name, values, ok) -> None:
        self.sent.append({"op": "service_response", "id": call_id, "service": name, "values": values, "result": ok})

    def call_service_async(self, name, args) -> WireFuture:
        future: WireFuture = WireFuture()
        self.calls.append(future)
        return future

    def publish(self, topic: str, msg: dict) -> None:
        for handler in list(self.topic_handlers.get(topic, [])):
            handler(msg)

    def call(self, service: str, call_id: str, args: dict) -> None:
        self.service_handlers[service]({"op": "call_service", "id": call_id, "service": service, "args": args})

    def close(self) -> None:
        pass


@pytest.fixture()
def rclpy(site):
    """rclpy, initialised; `rclpy.connection` is the lab's side."""
    connection = RecordingConnection()
    process._connection.append(connection)
    import rclpy as module

    module.init(args=["program"], signal_handler_options=0)
    module.connection = connection
    return module
