"""rosbridge v2 frames: parsing with limits, field checks, status messages.

A frame is a JSON object with a string `op` (the rosbridge v2 protocol of rosbridge_suite). Limits keep
a bad client from costing the server: a frame longer than MAX_FRAME characters closes the socket
(1009), nesting deeper than MAX_DEPTH is refused; every refusal is a `status` message at level
error that names the op and the field.
"""

from __future__ import annotations

import json
from typing import Any

MAX_FRAME = 1_600_000  # characters of one frame: a 640x480 rgb8 sensor_msgs/Image (base64) a bag plays
MAX_DEPTH = 32  # nesting of objects and arrays in one frame
MAX_STATUS = 2000  # characters of a status message's text: what a client sent is never echoed whole
Id = str | int | None  # a frame's "id" when it is a string or an integer (else None)
MAX_HEADERS = 32  # fields of a connection header a client gives (the lab's extension: advertise, call_service)
MAX_HEADER_KEY = 64  # characters of a header field's name
MAX_HEADER_VALUE = 1024  # characters of a header field's value
LEVELS = ("info", "warning", "error", "none")  # set_level; a level shows itself and the ones after it

# What one client, and all of them together, may hold open (a refusal names the cap; docs/reference/rosbridge.md,
# "Limits"). rosbridge_suite bounds a frame (max_message_size) and fragments; these bound what frames build.
MAX_CONNECTIONS = 128  # rosbridge clients at once; one more is closed with 1013 (try again later)
MAX_CLIENT_TOPICS = 256  # topics one client advertises
ENDPOINT_KINDS = ("publisher", "subscription", "client", "action_client")  # the entities the lab's `endpoints` op tells
MAX_TOPICS = 1024  # topics nodes publish or subscribe, all clients together (node topics)
MAX_CLIENT_SERVICES = 32  # services one client provides
MAX_SERVICES = 128  # services nodes provide, all clients together
MAX_CLIENT_TF_REPUBLISHED = 8  # /republish_tfs topics and tf2_web_republisher goals one client holds


class BadFrame(Exception):
    """A frame refused; the message names the op and the field."""


def parse(text: str) -> dict:
    """The frame as a dict with a string `op`, or BadFrame."""
    try:
        message = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise BadFrame(f"not a JSON message: {str(exc)[:200]}") from None
    if not isinstance(message, dict):
        raise BadFrame("a rosbridge message is a JSON object with an 'op' field")
    if depth(message) > MAX_DEPTH:
        raise BadFrame(f"message nested deeper than {MAX_DEPTH} levels")
    if not isinstance(message.get("op"), str):
        raise BadFrame("field 'op' must be a string (e.g. \"call_service\")")
    return message


def depth(value: Any) -> int:
    """Nesting depth of a JSON value (iterative: no recursion limit to hit)."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict):
            items = list(item.values())
        elif isinstance(item, list):
            items = item
        else:
            continue
        deepest = max(deepest, level)
        if deepest > MAX_DEPTH:
            return deepest
        stack.extend((child, level + 1) for child in items)
    return deepest


def field(
    message: dict, name: str, kind: type | tuple[type, ...], default: Any = ..., *, allow_none: bool = False
) -> Any:
    """message[name] if it is of `kind` (a bool is not an int), the default when absent, else BadFrame."""
    op = message.get("op")
    if name not in message or (message[name] is None and default is not ...):
        if default is ...:
            raise BadFrame(f"{op}: field '{name}' is required")
        return default
    value = message[name]
    kinds = kind if isinstance(kind, tuple) else (kind,)
    if value is None and allow_none:
        return None
    if (isinstance(value, bool) and bool not in kinds) or not isinstance(value, kinds):
        names = " or ".join(
            {
                str: "a string",
                int: "an integer",
                float: "a number",
                bool: "a boolean",
                dict: "an object",
                list: "an array",
            }.get(k, k.__name__)
            for k in kinds
        )
        raise BadFrame(f"{op}: field '{name}' must be {names}, got {json.dumps(value)[:80]}")
    return value


def name_field(message: dict, key: str) -> str:
    """A topic/service/action name field, absolute (`/name`)."""
    value = field(message, key, str)
    if not value.strip("/") or len(value) > 256 or any(c.isspace() for c in value):
        raise BadFrame(f"{message.get('op')}: field '{key}' must be a ROS name like /add_two_ints, got {value[:80]!r}")
    return "/" + value.strip("/")


def headers_field(message: dict) -> dict[str, str] | None:
    """The lab's extension `headers` (advertise, call_service): a ROS 1 connection header's extra
    fields, {str: str}, at most MAX_HEADERS of them, each name and value within its bound (a
    rosbridge client sends none: None)."""
    headers = field(message, "headers", dict, None)
    if headers is None:
        return None
    op = message.get("op")
    if len(headers) > MAX_HEADERS:
        raise BadFrame(f"{op}: field 'headers' holds at most {MAX_HEADERS} fields, got {len(headers)}")
    for key, value in headers.items():
        if not 0 < len(key) <= MAX_HEADER_KEY or "=" in key:
            raise BadFrame(
                f"{op}: field 'headers': a name of 1 to {MAX_HEADER_KEY} characters without '=', got {key[:80]!r}"
            )
        if not isinstance(value, str) or len(value) > MAX_HEADER_VALUE:
            shown = json.dumps(value)[:80]
            raise BadFrame(
                f"{op}: field 'headers.{key}' must be a string of at most {MAX_HEADER_VALUE} characters, got {shown}"
            )
    return headers


def status(level: str, msg: str, id_: Id = None) -> dict:
    if len(msg) > MAX_STATUS:
        msg = f"{msg[:MAX_STATUS]}... ({len(msg)} characters)"
    out: dict[str, str | int] = {"op": "status", "level": level, "msg": msg}
    if id_ is not None:
        out["id"] = id_
    return out
