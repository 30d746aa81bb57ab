"""roslib.message: a message or service class by its type name ('std_msgs/String'), as genpy made it."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["get_message_class", "get_service_class"]


def _class(type_name: str, kind: str) -> Any:
    package, _, name = type_name.replace(f"/{kind}/", "/").partition("/")
    if not package or not name:
        return None
    try:
        return getattr(importlib.import_module(f"{package}.{kind}"), name)
    except (ImportError, AttributeError, ValueError, LookupError):
        return None


def get_message_class(message_type: str, reload_on_error: bool = False) -> Any:
    """The class of 'pkg/Name' (None when there is none, as roslib answers)."""
    return _class(message_type, "msg")


def get_service_class(service_type: str, reload_on_error: bool = False) -> Any:
    return _class(service_type, "srv")
