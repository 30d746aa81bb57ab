"""A ROS 1 interface's md5sum, as genmsg computes it (genmsg's compute_md5_text): the definition's
constants (`TYPE NAME=VALUE`) then its fields (`TYPE NAME`), one a line, comments and blank lines
gone, a builtin type (a primitive, time, duration, arrays of them) written as it is and a nested
message's type replaced by that message's md5sum; a service's is the md5 of its request's text
followed by its response's. rospy's connection headers carry it (`_connection_header['md5sum']`)."""

from __future__ import annotations

import hashlib
from functools import cache
from typing import Any

from interfaces.parser import PRIMITIVES

_BUILTIN = {*PRIMITIVES, "time", "duration"} - {"wstring"}  # genmsg's is_builtin (ROS 1 has no wstring)


def md5_text(message_class: Any) -> str:
    """genmsg's md5 text of a message class (its `_definition`, its fields' classes)."""
    nested = {f.name: f.msg_class for f in message_class._fields}
    constants, fields = [], []
    for raw in message_class._definition.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if "=" in line:  # a constant: a string's value is the rest of the raw line (no comment in it)
            kind = line.split()[0]
            source = raw if kind == "string" else line
            name, _, value = source.partition(" ")[2].partition("=")
            constants.append(f"{kind} {name.strip()}={value.strip()}")
            continue
        kind, name = line.split()[:2]
        bare = kind.split("[", 1)[0]
        if bare in _BUILTIN:
            fields.append(f"{kind} {name}")
        elif nested.get(name) is not None:
            fields.append(f"{md5sum(nested[name])} {name}")
    return "\n".join(constants + fields)


@cache
def md5sum(interface: Any) -> str:
    """genmsg's md5sum of a message or service class (a service: its request's and response's texts)."""
    if hasattr(interface, "_request_class"):
        text = md5_text(interface._request_class) + md5_text(interface._response_class)
    else:
        text = md5_text(interface)
    return hashlib.md5(text.encode(), usedforsecurity=False).hexdigest()  # genmsg's checksum of a type
