"""The graph as the programs make it, for `hri-lab topic list|echo`: the programs' own topics (a
running talker's /chatter) are not the lab's HTTP topics, so these commands also ask the lab's
rosbridge endpoint (`ws://HOST:PORT/`, rosbridge protocol v2: rosapi's topics, a subscribe), as
ros2cli asks the ROS graph."""

from __future__ import annotations

import itertools
import json
from collections.abc import Iterator
from typing import Any

from websockets.sync.client import connect

_ids = itertools.count(1)
TIMEOUT_S = 10.0  # s to wait for rosapi's answer (a bound for a loaded machine)


def _ws_url(url: str) -> str:
    return url.replace("http://", "ws://").replace("https://", "wss://").rstrip("/") + "/"


def call(url: str, service: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
    """One rosbridge call_service; its values (an empty dict when it failed)."""
    ident = f"hri-lab-cli-{next(_ids)}"
    with connect(_ws_url(url), open_timeout=TIMEOUT_S) as ws:
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
    with connect(_ws_url(url), open_timeout=TIMEOUT_S) as ws:
        ws.send(json.dumps({"op": "subscribe", "id": f"hri-lab-cli-{next(_ids)}", "topic": topic, "type": type_name}))
        while True:
            message = json.loads(ws.recv())
            if message.get("op") == "publish" and message.get("topic") == topic:
                yield message.get("msg", {})
