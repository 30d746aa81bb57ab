"""A program's one connection to the lab: rosbridge v2 (JSON over a WebSocket) with the `websockets`
package's threaded client.

rospy and rclpy (rosclient/site) are layers over this: topics (advertise/publish/subscribe),
services (call_service; advertise_service, answered with service_response), ROS 2 actions
(send_action_goal/cancel_action_goal as a client; advertise_action, answered with action_feedback
and action_result, as a server). Incoming frames are read on one thread ("rosbridge-reader") and
handed to the handlers registered here; the layers decide on which thread the user's callbacks
run. The lab going away calls `on_lost` (by default: a clear message and exit status 1).
"""

from __future__ import annotations

import itertools
import json
import os
import sys
import threading
from collections.abc import Callable
from concurrent.futures import Future
from typing import Any
from urllib.parse import urlsplit, urlunsplit

import orjson
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from rosclient import delivery
from rosclient.delivery import LAB_QUEUE
from rosclient.headers import lab_headers

DEFAULT_URL = "http://127.0.0.1:8000"


EXIT_LAB_GONE = 1


# how the lab's publish frames begin (app/rosbridge/internal/shared.py: json.dumps of op, topic, msg)
PUBLISH_FRAME = b'{"op": "publish", "topic": "'


def decode(frame: str | bytes) -> Any:
    """A frame's JSON, read by orjson: a 640x480 image's frame (1.2 MB) in ~0.6 ms where the standard
    library's scanner takes ~1 ms on a quiet machine, and 1.1-1.2 ms against 1.7-1.8 ms at p50 in an
    image server's callbacks (docs/ros-programs-client.md#measured). NaN and Infinity, which orjson
    refuses and `json.dumps` writes, are read by the standard library. One difference stays: an
    integer beyond 64 bits, which no ROS field holds, is read as a float. Not JSON: ValueError."""
    try:
        return orjson.loads(frame)
    except orjson.JSONDecodeError:
        return json.loads(frame)


def _publish_topic(frame: bytes) -> str | None:
    """The topic of a publish frame in the lab's shape, read without decoding the frame; None for any
    other frame (decoded as usual)."""
    if not frame.startswith(PUBLISH_FRAME):
        return None
    start = len(PUBLISH_FRAME)
    end = frame.find(b'"', start, start + 1024)
    if end < 0 or not frame.startswith(b'", "msg": ', end) or b"\\" in frame[start:end]:
        return None
    try:
        return frame[start:end].decode()
    except UnicodeDecodeError:
        return None


class Frame(dict):
    """A publish frame already decoded (for the topic's other handlers, or addressed to one
    subscription), as an `undecoded` handler is given it: `message_of` reads its message."""


def message_of(frame: bytes | dict) -> dict | None:
    """The message of what an `undecoded` handler was given: a publish frame as it came (decoded here),
    a Frame, or the message itself (a test's); None for a frame that is not JSON."""
    if isinstance(frame, Frame):
        message = frame.get("msg")
        return message if isinstance(message, dict) else {}
    if isinstance(frame, dict):
        return frame
    try:
        decoded = decode(frame)
    except ValueError:
        return None
    message = decoded.get("msg") if isinstance(decoded, dict) else None
    return message if isinstance(message, dict) else {}


def framed(frame: bytes | dict) -> bytes | dict:
    """A publish frame as it came, decoded once (a Frame) for a handler that reads its header before
    its message (`sender_of`, then `message_of` when taken); anything else as it is."""
    if isinstance(frame, dict):
        return frame
    try:
        decoded = decode(frame)
    except ValueError:
        return frame
    return Frame(decoded) if isinstance(decoded, dict) else frame


def header_of(decoded: dict) -> dict:
    """A decoded publish frame's connection header, its publisher's ({} when the lab sent none)."""
    header = decoded.get("connection_header")
    return header if isinstance(header, dict) else {}


def sender_of(frame: bytes | dict) -> str | None:
    """The `callerid` of a publish frame's connection header, as an `undecoded` handler that asked for
    headers was given it (its publisher's client: app/rosbridge/capabilities/advertise.py); None when
    it carries none (the lab's own topics, a client without a header) or is not JSON."""
    decoded = framed(frame)
    if not isinstance(decoded, Frame):  # a message itself, or not a JSON object
        return None
    caller = header_of(decoded).get("callerid")
    return caller if isinstance(caller, str) else None


def websocket_url(url: str) -> str:
    """http(s)://host:port[/path] -> ws(s)://host:port/ (the lab's rosbridge endpoint is at /)."""
    parts = urlsplit(url if "://" in url else "http://" + url)
    scheme = {"http": "ws", "https": "wss"}.get(parts.scheme, parts.scheme)
    return urlunsplit((scheme, parts.netloc, parts.path or "/", "", ""))


class RosbridgeError(Exception):
    """A call the lab (or the node that serves it) answered as failed; the message is the reason."""


class Connection:
    def __init__(self, url: str | None = None, token: str | None = None) -> None:
        self.url = url or os.environ.get("HRI_LAB_URL", DEFAULT_URL)
        token = token if token is not None else os.environ.get("HRI_LAB_TOKEN")
        headers = lab_headers(self.url, token) or None
        try:
            self.ws = connect(
                websocket_url(self.url),
                additional_headers=headers,
                max_size=None,
                open_timeout=10,
                close_timeout=1,
                compression=None,  # images (/image_raw, 1.2 MB each) would be deflated and inflated at 30 Hz
                # no keepalive pings: a program behind on a 1 kHz topic reads the lab's pong behind its
                # backlog, and a live, slow program is not a lost lab (a lab that goes away closes the socket)
                ping_interval=None,
            )
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(
                f"cannot reach the lab at {self.url} ({exc}); start it with `hri-lab serve` "
                f"or give its address with --url / $HRI_LAB_URL"
            ) from None
        self.closing = False
        self.on_lost: Callable[[str], None] = _exit_lab_gone
        self._ids = itertools.count(1)
        self._lock = threading.Lock()
        self._calls: dict[str, Future] = {}
        self._goals: dict[str, tuple[Callable, Callable]] = {}  # id -> (on_feedback, on_result)
        self._refusals: dict[str, list[str]] = {}  # an op's id -> the lab's errors of it, for its sender
        self.topic_handlers: dict[str, list[Callable[[dict], None]]] = {}
        # handlers given each message with its publisher's connection header (rospy's subscribers)
        self.header_handlers: dict[str, list[Callable[[dict, dict], None]]] = {}
        # handlers given each publish frame undecoded, its bytes (rclpy's subscriptions: `message_of`)
        self.frame_handlers: dict[str, list[Callable[[bytes | dict], None]]] = {}
        self._subscriptions: dict[str, tuple[str, Callable[..., None]]] = {}  # subscribe id -> (topic, handler)
        self._with_header: set[str] = set()  # ids of calls answered with the server's connection header
        self.service_handlers: dict[str, Callable[[dict], None]] = {}
        self.action_handlers: dict[str, tuple[Callable[[dict], None], Callable[[dict], None]]] = {}
        self.status_handler: Callable[[dict], None] = _print_status
        # the lab's `endpoints` frames: the other programs' endpoints on this program's topics (rclpy's)
        self.endpoints_handler: Callable[[dict], None] | None = None
        self.rosout_refused: Callable[[str], None] = lambda reason: (
            None
        )  # the lab refused a /rosout line (process.py keeps it)
        delivery.reader_turns()  # the readers read the lab's messages as they come, while a callback computes
        self._reader = threading.Thread(target=self._read, name="rosbridge-reader", daemon=True)
        self._reader.start()

    def next_id(self, prefix: str) -> str:
        return f"{prefix}:{next(self._ids)}"

    def send(self, message: dict) -> None:
        try:
            self.ws.send(json.dumps(message))
        except ConnectionClosed:
            if not self.closing:
                self._lost("the connection closed while sending")

    def close(self) -> None:
        self.closing = True
        self.ws.close()

    # --- topics ---------------------------------------------------------------------------------
    def subscribe(
        self,
        topic: str,
        type_name: str,
        handler: Callable[..., None],
        queue_length: int = LAB_QUEUE,
        throttle_rate: int = 0,
        connection_header: bool = False,
        undecoded: bool = False,
        volatile: bool = False,
    ) -> str:
        """Hand `topic`'s messages to `handler`; with `connection_header` (the lab's extension), as
        `handler(msg, header)`, the header of the publisher that sent it ({} when the lab sent none);
        `undecoded`: as the publish frame's bytes, left for the taker to decode (`message_of`): a
        subscription whose queue drops what its callback cannot take never decodes those (30 images a
        second of 1.2 MB: the reader's JSON held the interpreter 1.6 ms each); with `connection_header`
        too, the frames carry the header, which `sender_of` reads. `volatile` (the lab's
        extension, rclpy's VOLATILE durability): none of what latched publishers kept; without it
        their history comes first, addressed to this subscription's id (_dispatch)."""
        sid = self.next_id(f"subscribe:{topic}")
        with self._lock:
            self._subscriptions[sid] = (topic, handler)
            if connection_header and not undecoded:
                self.header_handlers.setdefault(topic, []).append(handler)
            elif undecoded:
                self.frame_handlers.setdefault(topic, []).append(handler)
            else:
                self.topic_handlers.setdefault(topic, []).append(handler)
        frame = {
            "op": "subscribe",
            "id": sid,
            "topic": topic,
            "type": type_name,
            "queue_length": queue_length,
            "throttle_rate": throttle_rate,
        }
        if connection_header:
            frame["connection_header"] = True
        if volatile:
            frame["durability"] = "volatile"
        self.send(frame)
        return sid

    def unsubscribe(self, topic: str, sid: str, handler: Callable[..., None]) -> None:
        with self._lock:
            self._subscriptions.pop(sid, None)
            for table in (self.topic_handlers, self.header_handlers, self.frame_handlers):
                handlers = table.get(topic, [])
                if handler in handlers:
                    handlers.remove(handler)
        self.send({"op": "unsubscribe", "id": sid, "topic": topic})

    # --- services -------------------------------------------------------------------------------
    def call_service(self, name: str, args: dict, timeout: float | None = None) -> Any:
        """The response values; RosbridgeError with the reason when the call failed."""
        future = self.call_service_async(name, args)
        ok, values = future.result(timeout)
        if not ok:
            raise RosbridgeError(values if isinstance(values, str) else json.dumps(values))
        return values

    def call_service_async(self, name: str, args: dict, headers: dict[str, str] | None = None) -> Future:
        """A Future of (ok, values); with `headers` (the lab's extension: the extra fields of this
        client's connection header), of (ok, values, the server's connection header)."""
        call_id = self.next_id(f"call_service:{name}")
        future: Future = Future()
        frame: dict[str, Any] = {"op": "call_service", "id": call_id, "service": name, "args": args}
        with self._lock:
            self._calls[call_id] = future
            if headers is not None:
                self._with_header.add(call_id)
                frame["headers"] = headers
        self.send(frame)
        return future

    def advertise_service(
        self,
        name: str,
        type_name: str,
        handler: Callable[[dict], None],
        definition: str | None = None,
        check: bool = False,
    ) -> str | None:
        """Provide `name`; `definition` is the .srv text with its nested messages' (packages.full_text),
        which the lab shows and checks requests against (an extra field rosbridge_suite ignores).
        With `check`, the lab's refusal (e.g. another node provides the name) is returned, not printed,
        and the handler is not kept; None: the lab took it (or, from the reader thread, is told)."""
        previous = self.service_handlers.get(name)
        self.service_handlers[name] = handler
        advertise_id = self.next_id(f"advertise_service:{name}")
        refusals: list[str] = []
        if check:
            self._refusals[advertise_id] = refusals
        message = {"op": "advertise_service", "id": advertise_id, "service": name, "type": type_name}
        if definition is not None:
            message["definition"] = definition
        self.send(message)
        self.sync()  # as rospy.Service returns once the master has registered it
        self._refusals.pop(advertise_id, None)
        if not refusals:
            return None
        if previous is None:
            self.service_handlers.pop(name, None)
        else:
            self.service_handlers[name] = previous
        return refusals[0]

    def sync(self, timeout: float = 10.0) -> None:
        """Return once the lab has handled every op sent before: one round trip on this connection
        (the lab, like rosbridge_suite, handles a connection's ops in order). From the reader
        thread (a callback) it cannot wait for the answer and returns at once."""
        if threading.current_thread() is self._reader:
            return
        try:
            self.call_service_async("/rosapi/get_time", {}).result(timeout)
        except TimeoutError:
            pass  # a lab this slow still takes the ops in order; the caller goes on as rosbridge would

    def service_response(self, call_id: Any, name: str, values: Any, ok: bool) -> None:
        self.send({"op": "service_response", "id": call_id, "service": name, "values": values, "result": ok})

    # --- actions (ROS 2 ops) ----------------------------------------------------------------------
    def send_action_goal(
        self,
        action: str,
        type_name: str,
        args: dict,
        on_feedback: Callable[[dict], None],
        on_result: Callable[[dict], None],
    ) -> str:
        goal_id = self.next_id(f"send_action_goal:{action}")
        with self._lock:
            self._goals[goal_id] = (on_feedback, on_result)
        self.send(
            {
                "op": "send_action_goal",
                "id": goal_id,
                "action": action,
                "action_type": type_name,
                "args": args,
                "feedback": True,
            }
        )
        return goal_id

    def cancel_action_goal(self, action: str, goal_id: str) -> None:
        self.send({"op": "cancel_action_goal", "id": goal_id, "action": action})

    def advertise_action(
        self, name: str, type_name: str, on_goal: Callable[[dict], None], on_cancel: Callable[[dict], None]
    ) -> None:
        self.action_handlers[name] = (on_goal, on_cancel)
        self.send({"op": "advertise_action", "action": name, "type": type_name})
        self.sync()  # the program's "ready" line comes after the lab lists the action

    # --- reading ----------------------------------------------------------------------------------
    def _read(self) -> None:
        try:
            while True:
                # a text frame's bytes as they came: an image's (1.2 MB, 30 a second) is decoded only by
                # whoever takes it (message_of), not to a str first by the socket's reader
                frame = self.ws.recv(decode=False)
                topic = _publish_topic(frame) if self.frame_handlers else None
                if topic is not None:
                    with self._lock:
                        undecoded = list(self.frame_handlers.get(topic, ()))
                        decoded = topic in self.topic_handlers or topic in self.header_handlers
                    if undecoded and not decoded:
                        for handler in undecoded:
                            handler(frame)
                        continue
                try:
                    message = decode(frame)
                except ValueError:
                    continue
                if isinstance(message, dict):
                    self._dispatch(message)
        except ConnectionClosed:
            pass
        except Exception as exc:  # noqa: BLE001 - any failure of the socket is the lab gone
            if not self.closing:
                self._lost(str(exc))
                return
        if not self.closing:
            self._lost("the lab closed the connection")

    def _dispatch(self, message: dict) -> None:
        op = message.get("op")
        if op == "publish":
            self._publish(message)
        elif op == "service_response":
            self._service_response(message)
        elif op == "call_service":
            serve = self.service_handlers.get("/" + str(message.get("service", "")).strip("/"))
            if serve is not None:
                serve(message)
            else:
                self.service_response(message.get("id"), str(message.get("service")), "no such service here", False)
        elif op in ("action_feedback", "action_result"):
            with self._lock:
                entry = self._goals.get(str(message.get("id")))
                if op == "action_result":
                    self._goals.pop(str(message.get("id")), None)
            if entry is not None:
                entry[0 if op == "action_feedback" else 1](message)
        elif op in ("send_action_goal", "cancel_action_goal"):
            entry = self.action_handlers.get("/" + str(message.get("action", "")).strip("/"))
            if entry is not None:
                entry[0 if op == "send_action_goal" else 1](message)
        elif op == "status":
            self._status(message)
        elif op == "endpoints" and self.endpoints_handler is not None:  # other programs' (rclpy/_endpoints.py)
            self.endpoints_handler(message)

    def _publish(self, message: dict) -> None:
        """A publish frame decoded: its message to the topic's handlers (a latched one's to the one
        subscription it is addressed to)."""
        topic = str(message.get("topic"))
        with self._lock:
            handlers = list(self.topic_handlers.get(topic, ()))
            undecoded = list(self.frame_handlers.get(topic, ()))  # decoded already, for the topic's other handlers
            with_header = list(self.header_handlers.get(topic, ()))
            addressed = self._subscriptions.get(str(message.get("id"))) if "id" in message else None
        if addressed is not None and addressed[0] == topic:  # a latched message for one subscription
            handlers = [h for h in handlers if h is addressed[1]]
            undecoded = [h for h in undecoded if h is addressed[1]]
            with_header = [h for h in with_header if h is addressed[1]]
        for handler in handlers:
            handler(message.get("msg") or {})
        if undecoded:
            frame = Frame(message)
            for handler in undecoded:
                handler(frame)
        if with_header:
            header = header_of(message)
            for header_handler in with_header:
                header_handler(message.get("msg") or {}, header)

    def _service_response(self, message: dict) -> None:
        """A call's answer to the future its caller waits on: (result, values[, connection header])."""
        with self._lock:
            call_id = str(message.get("id"))
            future = self._calls.pop(call_id, None)
            wants_header = call_id in self._with_header
            self._with_header.discard(call_id)
        if future is not None and not future.done():
            answer: tuple = (bool(message.get("result", True)), message.get("values"))
            if wants_header:
                header = message.get("connection_header")
                answer += (header if isinstance(header, dict) else {},)
            future.set_result(answer)

    def _status(self, message: dict) -> None:
        """A status message: rosout's refusal, an op's refusal for its caller, else the status handler's."""
        id_ = str(message.get("id", ""))
        if id_ == "rosout":
            if message.get("level") == "error":
                self.rosout_refused(str(message.get("msg")))
        elif id_ in self._refusals and message.get("level") == "error":  # the op's refusal: raised by its caller
            self._refusals[id_].append(str(message.get("msg")))
        elif not id_.startswith("call_service:"):  # a failed call's reason reaches its caller instead
            self.status_handler(message)

    def _lost(self, reason: str) -> None:
        with self._lock:
            calls, self._calls = list(self._calls.items()), {}
            with_header, self._with_header = self._with_header, set()
        for call_id, future in calls:
            if not future.done():
                lost: tuple = (False, f"the lab at {self.url} went away")
                future.set_result(lost + ({},) if call_id in with_header else lost)
        self.on_lost(reason)


def _print_status(message: dict) -> None:
    if message.get("level") in ("error", "warning"):
        print(f"[{message['level'].upper()}] lab: {message.get('msg')}", file=sys.stderr, flush=True)


def _exit_lab_gone(reason: str) -> None:
    print(f"[FATAL] lost the lab ({reason}): the program stops", file=sys.stderr, flush=True)
    os._exit(EXIT_LAB_GONE)
