"""The graph as the programs make it, for `hri-lab topic list|echo|info|pub|hz|bw`, `node`, `param
delete`: the programs' own topics (a running talker's /chatter) are not the lab's HTTP topics, so
these commands also ask the lab's rosbridge endpoint (`ws://HOST:PORT/`, rosbridge protocol v2:
rosapi's topics, a subscribe, an advertise and its publishes), as ros2cli asks the ROS graph."""

from __future__ import annotations

import itertools
import json
import os
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

from websockets.sync.client import connect

if TYPE_CHECKING:
    from interfaces.packages import Interfaces

_ids = itertools.count(1)
HIDDEN = f"/_hri_lab_cli_{os.getpid()}"  # this command's own node: a hidden name (a leading _), as ROS 2 hides them
TIMEOUT_S = 10.0  # s to wait for rosapi's answer (a bound for a loaded machine)
# bytes of one WebSocket message the commands take: a camera image (/image_raw, 640x480 RGB) is 1.2 MB
# and more, the robot's URDF hundreds of kB; websockets' default, 1 MiB, refused an image ("message too big")
MAX_MESSAGE_BYTES = 2**24


def _ws_url(url: str) -> str:
    return url.replace("http://", "ws://").replace("https://", "wss://").rstrip("/") + "/"


def call(url: str, service: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
    """One rosbridge call_service; its values (an empty dict when it failed)."""
    ident = f"hri-lab-cli-{next(_ids)}"
    with connect(_ws_url(url), open_timeout=TIMEOUT_S, max_size=MAX_MESSAGE_BYTES) as ws:
        ws.send(json.dumps({"op": "node", "name": HIDDEN}))  # hidden, as ros2cli's own node is
        ws.send(json.dumps({"op": "call_service", "id": ident, "service": service, "args": args or {}}))
        while True:
            message = json.loads(ws.recv(timeout=TIMEOUT_S))
            if message.get("op") == "service_response" and message.get("id") == ident:
                return dict(message.get("values") or {}) if message.get("result", True) else {}


def topics(url: str) -> dict[str, str]:
    """Every topic of the graph: name -> its type (the programs' included)."""
    answer = call(url, "/rosapi/topics")
    return dict(zip(answer.get("topics", []), answer.get("types", []), strict=False))


def messages(url: str, topic: str, type_name: str) -> Iterator[dict[str, Any]]:
    """The messages published on `topic` from now on (rosbridge's subscribe)."""
    for message, _ in frames(url, topic, type_name):
        yield message


def frames(url: str, topic: str, type_name: str) -> Iterator[tuple[dict[str, Any], int]]:
    """The messages published on `topic` from now on, each with its frame's size (bytes of its JSON
    text, what `topic bw` counts where ros2 counts the CDR bytes)."""
    with connect(_ws_url(url), open_timeout=TIMEOUT_S, max_size=MAX_MESSAGE_BYTES) as ws:
        ws.send(json.dumps({"op": "subscribe", "id": f"hri-lab-cli-{next(_ids)}", "topic": topic, "type": type_name}))
        while True:
            text = ws.recv()
            message = json.loads(text)
            if message.get("op") == "publish" and message.get("topic") == topic:
                yield message.get("msg", {}), len(text.encode() if isinstance(text, str) else text)


def endpoints(url: str, kind: str, name: str) -> list[dict[str, Any]]:
    """The entities of `kind` (publisher, subscription, client) on `name`, each {"node", "qos"}: as
    the programs told the lab (the lab's `/rosapi/endpoints`); a client that told none is one
    entity of unknown QoS."""
    return list(call(url, "/rosapi/endpoints", {"kind": kind, "name": name}).get("endpoints", []))


class Refused(Exception):
    """The lab refused a frame of this command (its status message)."""


def publish(
    url: str,
    topic: str,
    type_name: str,
    messages: Iterator[dict[str, Any]],
    period_s: float,
    wait_for: int,
    waiting: Callable[[], None],
) -> None:
    """`topic pub`: advertise `topic`, wait until `wait_for` subscriptions are on it (`waiting()` told
    once when it must wait), then publish each of `messages` every `period_s` s (the first at once);
    Refused with the lab's reason."""
    with connect(_ws_url(url), open_timeout=TIMEOUT_S, max_size=MAX_MESSAGE_BYTES) as ws:
        link = _Link(ws)
        ws.send(json.dumps({"op": "node", "name": HIDDEN}))
        ws.send(json.dumps({"op": "advertise", "id": "pub", "topic": topic, "type": type_name}))
        link.call("/rosapi/get_time")  # the advertise handled: refused or not
        told = False
        while len(link.call("/rosapi/subscribers", {"topic": topic}).get("subscribers", [])) < wait_for:
            if not told:
                told = True
                waiting()
            time.sleep(WAIT_STEP_S)
        due = time.monotonic()
        for message in messages:
            time.sleep(max(0.0, due - time.monotonic()))
            ws.send(json.dumps({"op": "publish", "id": "pub", "topic": topic, "msg": message}))
            link.call("/rosapi/get_time")  # handled before the next (and before the socket closes)
            due += period_s


WAIT_STEP_S = 0.1  # s between looks for a matching subscription (ros2 topic pub's)


class _Link:
    """One rosbridge connection's calls, answered in order; a refusal of an earlier frame raises."""

    def __init__(self, ws: Any) -> None:
        self.ws = ws

    def call(self, service: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
        ident = f"hri-lab-cli-{next(_ids)}"
        self.ws.send(json.dumps({"op": "call_service", "id": ident, "service": service, "args": args or {}}))
        while True:
            message = json.loads(self.ws.recv(timeout=TIMEOUT_S))
            if message.get("op") == "status" and message.get("level") == "error":
                raise Refused(str(message.get("msg")))
            if message.get("op") == "service_response" and message.get("id") == ident:
                return dict(message.get("values") or {})


# --- `hri-lab node list|info`, `hri-lab interface show` ---------------------------------------------------
def ros2_type(type_name: str, kind: str) -> str:
    """`pkg/Name` as ROS 2 names it: `pkg/msg/Name` (srv, action); a ROS 2 name stays."""
    parts = type_name.split("/")
    return f"{parts[0]}/{kind}/{parts[1]}" if len(parts) == 2 else type_name


def node_list(url: str) -> list[str]:
    names = {"/" + n.strip("/") for n in call(url, "/rosapi/nodes").get("nodes", [])}
    return sorted(n for n in names if not n.rsplit("/", 1)[-1].startswith("_"))  # hidden ones, as ros2 node list


def node_info(
    url: str, name: str, services: dict[str, str] | None = None, actions: dict[str, str] | None = None
) -> str:
    """What `ros2 node info NAME` prints. `services`, `actions` (name -> type): the graph's, whose
    clients and servers the node's sections list as the lab knows them (`/rosapi/endpoints`: the
    clients the rclpy programs told, an action's server); a client of a name not among them is not seen."""
    name = "/" + name.strip("/")
    if name not in node_list(url):
        raise LookupError(f"Unable to find node '{name}'")
    details = call(url, "/rosapi/node_details", {"node": name})
    types = topics(url)

    def section(title: str, lines: list[str]) -> list[str]:
        return [f"  {title}:", *(f"    {line}" for line in lines)]

    def topic_lines(field: str) -> list[str]:
        return [f"{t}: {ros2_type(types.get(t, ''), 'msg')}" for t in sorted(details.get(field, []))]

    served = []
    for service in sorted(details.get("services", [])):
        kind = call(url, "/rosapi/service_type", {"service": service}).get("type", "")
        served.append(f"{service}: {ros2_type(kind, 'srv')}")

    def of_node(kind: str, named: dict[str, str] | None, interface: str) -> list[str]:
        return [
            f"{n}: {ros2_type(t, interface)}"
            for n, t in sorted((named or {}).items())
            if any(entity["node"] == name for entity in endpoints(url, kind, n))
        ]

    lines = [
        name,
        *section("Subscribers", topic_lines("subscribing")),
        *section("Publishers", topic_lines("publishing")),
        *section("Service Servers", served),
        *section("Service Clients", of_node("client", services, "srv")),
        *section("Action Servers", of_node("action_server", actions, "action")),
        *section("Action Clients", of_node("action_client", actions, "action")),
    ]
    return "\n".join(lines)


INTERFACE_HEADINGS = {"msg": "Messages:", "srv": "Services:", "action": "Actions:"}  # ros2 interface list's


def interface_list(kinds: tuple[str, ...]) -> str:
    """`ros2 interface list [-m] [-s] [-a]` (ros2interface/verb/list.py): the shipped interfaces of
    each kind under its heading, `    pkg/kind/Name` by package and name."""
    from interfaces.packages import Interfaces

    shipped = Interfaces([])
    lines = []
    for kind in kinds:
        lines.append(INTERFACE_HEADINGS[kind])
        lines += [
            f"    {package}/{kind}/{name}" for package, names in shipped.available(kind).items() for name in names
        ]
    return "\n".join(lines)


def interface_package(package: str, kinds: tuple[str, ...]) -> str:
    """`ros2 interface package PKG [-m] [-s] [-a]` (ros2interface/verb/package.py): its shipped
    interfaces of those kinds, `pkg/kind/Name` each; LookupError for a package the lab lacks."""
    from interfaces.packages import KINDS, Interfaces

    shipped = Interfaces([])
    if not shipped.is_package(package):
        raise LookupError(f"Unknown package '{package}'")
    found = [
        f"{package}/{kind}/{name}"
        for kind in KINDS
        if kind in kinds
        for name in shipped.available(kind).get(package, [])
    ]
    return "\n".join(found)


def interface_packages(kinds: tuple[str, ...]) -> list[str]:
    """`ros2 interface packages [-m] [-s]`: the shipped packages with interfaces of those kinds, sorted."""
    from interfaces.packages import Interfaces

    shipped = Interfaces([])
    return sorted({package for kind in kinds for package in shipped.available(kind)})


def interface_text(type_name: str, comments: str = "top") -> str:
    """`ros2 interface show TYPE` (ros2interface/verb/show.py): the definition of `pkg/msg/Name`
    (or srv, action; `pkg/Name` any of them) line by line as its file has it, each field of a message
    type followed by that type's definition one tab further in; the comments and blank lines of the
    top level shown (`top`, the default), of every level (`all`: --all-comments) or of none (`none`:
    --no-comments)."""
    from interfaces.packages import KINDS, Interfaces

    parts = type_name.strip("/").split("/")
    if len(parts) == 3 and parts[1] in KINDS:
        package, kinds, name = parts[0], [parts[1]], parts[2]
    elif len(parts) == 2:
        package, kinds, name = parts[0], list(KINDS), parts[1]
    else:
        raise LookupError(f"Invalid name '{type_name}': a type is pkg/msg/Name, pkg/srv/Name or pkg/action/Name")
    shipped = Interfaces([])
    for kind in kinds:
        text = _definition(shipped, package, kind, name)
        if text is not None:
            lines: list[str] = []
            _show(shipped, text, package, lines, comments != "none", comments == "all", 0, {f"{package}/{name}"})
            return "\n".join(lines)
    raise LookupError(f"Unknown interface '{type_name}'")


def _definition(shipped: Interfaces, package: str, kind: str, name: str) -> str | None:
    path = shipped.find(package, kind, name)
    return None if path is None else path.read_text(encoding="utf-8")


def _show(
    shipped: Interfaces,
    text: str,
    package: str,
    out: list[str],
    comments: bool,
    nested_comments: bool,
    indent: int,
    chain: set[str],
) -> None:
    """One definition's lines into `out`, a message-typed field's definition after it, one tab in
    (a type already on the chain, which ROS refuses, is not expanded again)."""
    from interfaces.parser import FIELD_LINE, PRIMITIVES, qualify, without_comment

    for raw in text.splitlines():
        line = raw.rstrip()
        code = without_comment(line)
        if not comments:
            if not code:
                continue  # a blank line or a comment
            line = line[: len(line) - len(line.lstrip())] + code  # a trailing comment cut
        out.append("\t" * indent + line if line else "")
        found = FIELD_LINE.match(code)
        if found is None or found.group(6):  # not a field, or a constant
            continue
        nested = qualify(found.group(1), package)
        if nested.split("<=")[0] in PRIMITIVES or "/" not in nested or nested in chain:
            continue
        nested_package, nested_name = nested.split("/", 1)
        definition = _definition(shipped, nested_package, "msg", nested_name)
        if definition is not None:
            _show(
                shipped, definition, nested_package, out, nested_comments, nested_comments, indent + 1, chain | {nested}
            )
