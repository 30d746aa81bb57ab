"""What rospy and rclpy share in one program: the lab connection (made when the program first
initialises ROS), ROS names, wall time, the /rosout publisher and the shutdown state.

`hri-lab run` (rosclient/run.py) starts the program with $HRI_LAB_URL, $HRI_LAB_TOKEN and the
interface finder installed; a program started otherwise (plain `python`) connects to the same
variables' lab.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from interfaces.packages import full_text
from rosclient.connection import Connection
from rosclient.delivery import Callbacks

POLL = 0.1  # s between looks at the lab's registry while waiting for a service or an action server

_lock = threading.Lock()
_connection: list[Connection] = []
shutdown_event = threading.Event()
shutdown_reason: list[str] = []
_advertised: set[str] = set()
_headers: dict[str, dict[str, str]] = {}  # topic -> its connection header's extra fields (rospy's)
_latched: dict[str, int] = {}  # topic -> the history depth the lab keeps for late subscribers (advertise's latch)
_lifespans: dict[str, float] = {}  # topic -> s a kept message lives (rclpy's QoS lifespan; advertise's `lifespan`)
_publishers: dict[str, int] = {}  # topic -> the publisher objects of it in this program (rospy's and rclpy's)
# callbacks running now on the program's threads (rospy's subscribers, timers, services): `with callbacks:` around
# one; the program's end waits for them (delivery.CALLBACK_GRACE_S)
callbacks = Callbacks()


def ensure_interfaces() -> None:
    """The interface finder, when the program was not started by boot.py (plain `python FILE`)."""
    from rosclient import interfaces

    if not any(isinstance(f, interfaces.Finder) for f in sys.meta_path):
        interfaces.install(interfaces.workspace_roots(Path(sys.argv[0] or "."), os.environ.get("HRI_LAB_WORKSPACE")))


def use_ros1() -> None:
    """ROS 1's standard messages (a Header with seq) for a rospy program's classes made from now on."""
    from rosclient import interfaces

    ensure_interfaces()
    for finder in sys.meta_path:
        if isinstance(finder, interfaces.Finder):
            finder.interfaces.use_ros1()


def connection() -> Connection:
    with _lock:
        if not _connection:
            made = Connection()
            made.rosout_refused = rosout_refused
            _connection.append(made)
        return _connection[0]


def connected() -> bool:
    return bool(_connection)


remaps: dict[str, str] = {}  # resolved name -> the name it is remapped to (rospy's `name:=other` arguments)


def resolve(name: str, node_name: str = "", namespace: str = "/") -> str:
    """A ROS name made absolute: `~x` is private to the node, `x` relative to the namespace; then
    remapped when the program was started with `x:=y`."""
    if name.startswith("~"):
        resolved = "/" + "/".join(p for p in (namespace.strip("/"), node_name.strip("/"), name[1:].strip("/")) if p)
    elif name.startswith("/"):
        resolved = "/" + name.strip("/")
    else:
        resolved = "/" + "/".join(p for p in (namespace.strip("/"), name.strip("/")) if p)
    return remaps.get(resolved, resolved)


def advertise_once(
    topic: str,
    type_name: str,
    msg_class: Any = None,
    headers: dict[str, str] | None = None,
    latch: int = 0,
    lifespan_s: float = 0.0,
) -> None:
    """Advertise a topic once; with its message class, its full definition goes along (beyond
    rosbridge's fields, as ROS's connection header carries it): `hri-lab bag record` writes it into
    the bag's schema, so a program's own types are in the file. `headers`: fields of the topic's
    connection header (rospy's `Publisher(headers=...)`, the lab's extension), added to the ones
    earlier publishers of the topic gave (as rospy's publishers of a topic share one header): new
    ones advertise the topic again. `latch`: the messages the lab keeps for a late subscriber (rclpy's
    TRANSIENT_LOCAL depth, rospy's latch: 1; rosbridge's `latch` and `queue_size`), the deepest of
    the topic's publishers' (a deeper one advertises the topic again), each kept message living
    `lifespan_s` (0: for ever; the lab's extension), as the deeper publisher's QoS says."""
    if not headers and topic in _advertised and latch <= _latched.get(topic, 0):  # every publish passes here
        return
    with _lock:
        merged = {**_headers.get(topic, {}), **(headers or {})}
        fresh = topic not in _advertised
        deeper = latch > _latched.get(topic, 0)
        if not fresh and merged == _headers.get(topic, {}) and not deeper:
            return
        _advertised.add(topic)
        if merged:
            _headers[topic] = merged
        if deeper:
            _latched[topic] = latch
            if lifespan_s > 0:
                _lifespans[topic] = lifespan_s
    frame: dict[str, Any] = {"op": "advertise", "topic": topic, "type": type_name}
    if fresh and msg_class is not None and hasattr(msg_class, "_fields"):
        frame["definition"] = full_text(msg_class)
    if merged:
        frame["headers"] = merged
    if _latched.get(topic):
        frame.update(latch=True, queue_size=_latched[topic])
    if topic in _lifespans:
        frame["lifespan"] = _lifespans[topic]
    connection().send(frame)


def unadvertise(topic: str) -> None:
    """This program no longer publishes `topic` (a later publish advertises it again)."""
    if topic in _advertised:
        _advertised.discard(topic)
        _headers.pop(topic, None)
        _latched.pop(topic, None)
        _lifespans.pop(topic, None)
        connection().send({"op": "unadvertise", "topic": topic})


def add_publisher(
    topic: str,
    type_name: str,
    msg_class: Any = None,
    headers: dict[str, str] | None = None,
    latch: int = 0,
    lifespan_s: float = 0.0,
) -> None:
    """A publisher object of `topic` made: the program advertises the topic while it holds one (as
    rospy's publishers of one topic share its connection, counted)."""
    with _lock:
        _publishers[topic] = _publishers.get(topic, 0) + 1
    advertise_once(topic, type_name, msg_class, headers, latch, lifespan_s)


def remove_publisher(topic: str) -> None:
    """A publisher object of `topic` gone: the last one unadvertises it."""
    with _lock:
        left = _publishers.get(topic, 0) - 1
        if left > 0:
            _publishers[topic] = left
            return
        _publishers.pop(topic, None)
    unadvertise(topic)


def publishers_of(topic: str) -> int:
    """This program's publisher objects of `topic`."""
    return _publishers.get(topic, 0)


node_names: list[str] = []  # the nodes this program runs, as it named them (rospy's init_node, rclpy's Node)


def declare_node(name: str) -> None:
    """Tell the lab a node's full name: errors, rosapi, /rosout and the dashboard show it
    (app/rosbridge/capabilities/node.py), not the connection's /rosbridge_client_N."""
    if name not in node_names:
        node_names.append(name)
        connection().send({"op": "node", "name": name})


def publish(topic: str, type_name: str, msg: dict) -> None:
    advertise_once(topic, type_name)
    connection().send({"op": "publish", "topic": topic, "msg": msg})


def service_names() -> set[str]:
    return set(connection().call_service("/rosapi/services", {}, timeout=10).get("services", []))


def action_names() -> set[str]:
    return set(connection().call_service("/rosapi/action_servers", {}, timeout=10).get("action_servers", []))


def wait_until(test: Callable[[], bool], timeout: float | None) -> bool:
    """Poll `test` every POLL s until true (True) or `timeout` s passed (False); None waits forever."""
    deadline = None if timeout is None or timeout < 0 else time.monotonic() + timeout
    while not shutdown_event.is_set():
        if test():
            return True
        if deadline is not None and time.monotonic() >= deadline:
            return False
        time.sleep(POLL if deadline is None else max(0.0, min(POLL, deadline - time.monotonic())))
    return False


def stamp_now() -> dict:
    now = time.time()
    sec = int(now)
    return {"sec": sec, "nanosec": int((now - sec) * 1e9)}


ROSOUT_ID = "rosout"  # the id of /rosout's frames: a refusal of them is never shown, it ends the publishing
_rosout_refused: list[str] = []


def rosout(msg: dict, type_name: str) -> None:
    """A log line on /rosout (only once the program is connected: logging never connects; a lab that
    refuses the program's /rosout lines gets no more of them)."""
    if not _connection or shutdown_event.is_set() or _rosout_refused:
        return
    try:
        conn = _connection[0]
        if "/rosout" not in _advertised:
            _advertised.add("/rosout")
            conn.send({"op": "advertise", "id": ROSOUT_ID, "topic": "/rosout", "type": type_name})
        conn.send({"op": "publish", "id": ROSOUT_ID, "topic": "/rosout", "msg": msg})
    except Exception:  # noqa: BLE001 - a log line never fails the program
        pass


def rosout_refused(reason: str) -> None:
    _rosout_refused.append(reason)


def ok() -> bool:
    return not shutdown_event.is_set()


_shutdown_hooks: list[Callable[[], None]] = []


def on_shutdown(hook: Callable[[], None]) -> None:
    """`hook()` when the program shuts down (e.g. rclpy's waits look again)."""
    _shutdown_hooks.append(hook)


def shutdown(reason: str = "") -> None:
    if not shutdown_event.is_set():
        shutdown_reason.append(reason)
        shutdown_event.set()
        for hook in list(_shutdown_hooks):
            hook()


def close() -> None:
    shutdown("")
    callbacks.wait()
    if _connection:
        _connection[0].close()


def program_args(argv: list[str] | None = None) -> tuple[list[str], list[str]]:
    """argv split into the program's own arguments and the ones after --ros-args (to --, or the end)."""
    argv = list(sys.argv if argv is None else argv)
    if "--ros-args" not in argv:
        return argv, []
    i = argv.index("--ros-args")
    rest = argv[i + 1 :]
    end = rest.index("--") if "--" in rest else len(rest)
    return argv[:i] + rest[end + 1 :], rest[:end]


def parse_value(text: str) -> Any:
    """A parameter value given as text (`-p name:=value`, `_name:=value`, launch files): YAML's
    reading of it, as ROS does."""
    import yaml

    try:
        return yaml.safe_load(text)
    except yaml.YAMLError:
        return text


def env_flag(name: str) -> bool:
    return os.environ.get(name, "") not in ("", "0")
