"""The client libraries of rosclient/site imported in this process, as a program imports them
(the site folder on sys.path, the interface finder installed); everything they changed undone after.
A RecordingConnection stands for the lab's: what the program sends is kept, what the lab sends is
fed to the handlers."""

import sys
from concurrent.futures import Future as WireFuture

import pytest

from interfaces import sequences
from rosclient import boot, process
from rosclient.connection import Frame

GENERATED = ("std_msgs", "example_interfaces", "rcl_interfaces", "builtin_interfaces", "geometry_msgs", "tf2_msgs", "sensor_msgs",
             "action_msgs", "unique_identifier_msgs")  # fmt: skip


class RecordingConnection:
    """The lab's side of the program's connection: ops sent are recorded; a service advertised is
    taken (no refusal); a call's wire future is left for the test to answer."""

    def __init__(self) -> None:
        self.sent: list[dict] = []
        self.topic_handlers: dict[str, list] = {}
        self.service_handlers: dict[str, object] = {}
        self.calls: list[WireFuture] = []
        self.with_header: set = set()
        self.framed: set = set()  # undecoded handlers that asked for connection headers (rclpy's subscriptions)
        self.endpoints_handler = None  # the lab's `endpoints` frames to the program (rclpy/_endpoints.py)
        self.queue_lengths: dict[str, int] = {}  # what each subscription asked the lab to hold for it
        self.volatile: dict[str, bool] = {}  # whether each topic's newest subscription asked for no latched history

    def send(self, message: dict) -> None:
        self.sent.append(message)

    def subscribe(
        self,
        topic,
        type_name,
        handler,
        queue_length=0,
        throttle_rate=0,
        connection_header=False,
        undecoded=False,
        volatile=False,
    ) -> str:  # an undecoded handler takes the message itself too
        self.topic_handlers.setdefault(topic, []).append(handler)
        self.queue_lengths[topic] = queue_length
        self.volatile[topic] = volatile
        if connection_header and not undecoded:  # handler(msg, header): the lab relayed no publisher's header here
            self.with_header.add(handler)
        if connection_header and undecoded:  # handler(frame): the publish frame, with its header when one is given
            self.framed.add(handler)
        return f"subscribe:{topic}"

    def unsubscribe(self, topic, sid, handler) -> None:
        self.topic_handlers[topic].remove(handler)
        self.sent.append({"op": "unsubscribe", "topic": topic})  # the op the real connection sends

    def advertise_service(self, name, type_name, handler, definition=None, check=False) -> str | None:
        self.service_handlers[name] = handler
        return None

    def service_response(self, call_id, name, values, ok) -> None:
        self.sent.append({"op": "service_response", "id": call_id, "service": name, "values": values, "result": ok})

    def call_service_async(self, name, args) -> WireFuture:
        future: WireFuture = WireFuture()
        self.calls.append(future)
        return future

    def publish(self, topic: str, msg: dict, sender: str | None = None) -> None:
        """`msg` on `topic` to its handlers, as the lab relays it; `sender`: the `callerid` of its
        publisher's connection header (the program that published it), for the handlers that asked."""
        frame = Frame(
            {
                "op": "publish",
                "topic": topic,
                "msg": msg,
                **({"connection_header": {"callerid": sender}} if sender else {}),
            }
        )
        for handler in list(self.topic_handlers.get(topic, [])):
            if handler in self.with_header:
                handler(msg, {"callerid": sender} if sender else {})
            else:
                handler(frame if handler in self.framed else msg)

    def call(self, service: str, call_id: str, args: dict) -> None:
        self.service_handlers[service]({"op": "call_service", "id": call_id, "service": service, "args": args})

    def close(self) -> None:
        pass


@pytest.fixture
def site():
    saved_path, saved_meta = list(sys.path), list(sys.meta_path)
    saved_hooks = list(process._shutdown_hooks)
    sys.path.insert(0, str(boot.SITE))
    process.ensure_interfaces()
    try:
        yield
    finally:
        sequences.typed[0] = False  # rclpy's typed arrays (its import turns them on)
        for advertised in (
            process._advertised,
            process._headers,
            process._latched,
            process._lifespans,
            process._publishers,
        ):
            advertised.clear()  # the topics it advertised: the next test's connection has none
        process._connection.clear()
        process.shutdown_event.clear()
        process.shutdown_reason.clear()
        process._shutdown_hooks[:] = saved_hooks
        sys.path[:] = saved_path
        sys.meta_path[:] = saved_meta
        for name in [
            n
            for n in sys.modules
            if n.split(".")[0] in ("rclpy", "rospy", "tf2_ros", "tf", "sensor_msgs_py", *GENERATED)
        ]:
            del sys.modules[name]


@pytest.fixture
def rclpy(site):
    """rclpy imported as a program imports it (`site`), initialised over a RecordingConnection;
    `rclpy.connection` is the lab's side."""
    connection = RecordingConnection()
    process._connection.append(connection)
    import rclpy as module

    module.init(args=["program"], signal_handler_options=0)
    module.connection = connection
    return module
