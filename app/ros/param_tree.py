"""ROS 1's parameter server: one tree of names (`/ns/sub/name`), any JSON value at any name, set,
read, listed, searched and deleted by anyone (rospy's get/set/has/delete_param, `rosparam`,
roslibpy's `Param`, rosapi). Setting a dict sets the subtree; getting a namespace answers the
subtree as a dict; `names()` lists the leaves, as the ROS master's getParamNames does.

It stands beside the lab's declared ROS 2 parameters (app/ros/params.py), which keep their types
and ranges: a ROS 1 name `/node/param` that a declared parameter has is that parameter (read and
set through its declaration), so `rospy.get_param('/cooperative_lifting/mu')` reads the lab's.
Limits keep a client from filling the server: MAX_ENTRIES leaves, values checked like a parameter
file (app/ros/params.py's limits). A name given as `read_only` (the lab's `/robot_description`) is
read like any other; setting or deleting it (or a namespace over it, or a name under it) is refused
with `read_only`'s reason; setting or deleting the root keeps it."""

from __future__ import annotations

import copy
import json
import threading
from typing import TypeVar, overload

from interfaces.json_value import JSON

MAX_ENTRIES = 10_000  # leaves in the tree
MAX_VALUE_CHARS = 100_000  # a value as JSON text
NAME_CHARS = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_/~")


class ParamError(ValueError):
    """A name or value the parameter server refuses (the reason is the message)."""


def canonical(name: str, namespace: str = "/") -> str:
    """A ROS 1 graph name as the master keys it: `a/b` in namespace `/ns` -> `/ns/a/b`; `/a/b/` -> `/a/b`."""
    if not isinstance(name, str) or not name.strip():
        raise ParamError("a parameter name is a non-empty string like /ns/name")
    name = name.strip()
    if not set(name) <= NAME_CHARS or "//" in name.strip("/") or len(name) > 256:
        raise ParamError(f"'{name[:80]}' is not a ROS name (letters, digits, _ and / only)")
    if not name.startswith("/"):
        name = namespace.rstrip("/") + "/" + name
    return "/" + name.strip("/") if name.strip("/") else "/"


D = TypeVar("D")  # get's default


def _check_value(value: object) -> None:
    try:
        text = json.dumps(value, allow_nan=False)
    except (TypeError, ValueError):
        raise ParamError("a parameter value is JSON: a number (finite), string, bool, list or dict") from None
    if len(text) > MAX_VALUE_CHARS:
        raise ParamError(f"a parameter value is at most {MAX_VALUE_CHARS} characters of JSON")


def _leaves(prefix: str, value: JSON) -> list[str]:
    if isinstance(value, dict) and value:
        return [n for key, child in value.items() for n in _leaves(f"{prefix.rstrip('/')}/{key}", child)]
    return [prefix]


class ParameterTree:
    """The tree: nested dicts under "/". Thread-safe (HTTP, rosapi and the CLI call it at once)."""

    def __init__(self, read_only: dict[str, tuple[JSON, str]] | None = None) -> None:
        """read_only: name -> (value, why it is read-only: the refusal's reason)."""
        self._root: dict[str, JSON] = {}
        self._lock = threading.Lock()
        self._read_only = {canonical(name): entry for name, entry in (read_only or {}).items()}
        for value, _ in self._read_only.values():
            _check_value(value)
        self._keep_read_only(self._root)

    def _refuse_read_only(self, name: str, verb: str) -> None:
        target = canonical(name)
        for fixed, (_, why) in self._read_only.items():
            if target == fixed or fixed.startswith(target.rstrip("/") + "/") or target.startswith(fixed + "/"):
                raise ParamError(f"cannot {verb} {target}: {fixed} is read-only ({why})")

    def _keep_read_only(self, root: dict[str, JSON]) -> None:
        """The read-only names put back into a new root (under the lock)."""
        for name, (value, _) in self._read_only.items():
            node = root
            parts = self._parts(name)
            for part in parts[:-1]:
                child = node.get(part)
                if not isinstance(child, dict):
                    child = node[part] = {}
                node = child
            node[parts[-1]] = copy.deepcopy(value)

    @staticmethod
    def _parts(name: str) -> list[str]:
        return [p for p in canonical(name).split("/") if p]

    def set(self, name: str, value: JSON) -> None:
        _check_value(value)
        parts = self._parts(name)
        if parts:
            self._refuse_read_only(name, "set")
        with self._lock:
            if not parts:  # the root: the whole tree (a dict), as the master allows
                if not isinstance(value, dict):
                    raise ParamError("the root namespace / can only be set to a dict")
                candidate = copy.deepcopy(value)
                self._keep_read_only(candidate)
                self._fits(candidate)
                self._root = candidate
                return
            node = self._root
            for part in parts[:-1]:
                child = node.get(part)
                if not isinstance(child, dict):
                    child = node[part] = {}
                node = child
            old = node.get(parts[-1], _MISSING)
            node[parts[-1]] = copy.deepcopy(value)
            try:
                self._fits(self._root)
            except ParamError:
                if isinstance(old, _Missing):
                    del node[parts[-1]]
                else:
                    node[parts[-1]] = old
                raise

    @staticmethod
    def _fits(root: dict[str, JSON]) -> None:
        if len(_leaves("/", root)) > MAX_ENTRIES:
            raise ParamError(f"the parameter server holds at most {MAX_ENTRIES} parameters")

    @overload
    def get(self, name: str) -> JSON: ...

    @overload
    def get(self, name: str, default: D) -> JSON | D: ...

    def get(self, name: str, default: object = None) -> object:
        """The value (a namespace: its subtree as a dict), or `default` when it is not set."""
        node: JSON = self._root
        with self._lock:
            for part in self._parts(name):
                if not isinstance(node, dict) or part not in node:
                    return default
                node = node[part]
            return copy.deepcopy(node)

    def has(self, name: str) -> bool:
        return self.get(name, _MISSING) is not _MISSING

    def delete(self, name: str) -> bool:
        """Delete a name (a namespace: all under it); False when it was not set."""
        parts = self._parts(name)
        if parts:
            self._refuse_read_only(name, "delete")
        with self._lock:
            if not parts:
                self._root = {}
                self._keep_read_only(self._root)
                return True
            node: JSON = self._root
            for part in parts[:-1]:
                if not isinstance(node, dict) or part not in node:
                    return False
                node = node[part]
            if not isinstance(node, dict) or parts[-1] not in node:
                return False
            del node[parts[-1]]
            return True

    def names(self) -> list[str]:
        """Every leaf's full name, sorted (getParamNames)."""
        with self._lock:
            return sorted(n for n in _leaves("/", self._root) if n != "/") if self._root else []

    def search(self, key: str, namespace: str = "/") -> str | None:
        """rospy.search_param: the nearest `key` from `namespace` up to the root (its first part
        decides, as in ROS 1), or None."""
        if not isinstance(key, str) or not key.strip().strip("/"):
            raise ParamError("search_param: the key is a relative name like 'robot_description'")
        key = key.strip().lstrip("~").strip("/")
        first = key.split("/")[0]
        parts = self._parts(namespace)
        for depth in range(len(parts), -1, -1):
            base = "/" + "/".join(parts[:depth]) if depth else ""
            if self.has(f"{base}/{first}"):
                return f"{base}/{key}"
        return None


class _Missing:
    pass


_MISSING = _Missing()
