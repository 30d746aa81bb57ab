"""Interface packages: `<pkg>/msg|srv|action/<Name>.<kind>` found in search roots (a program's
workspace first, then the definitions shipped in interfaces/share: the standard packages and
the lab's `hri_lab`), parsed and made classes, on demand and cached:

- a message: a `Message` subclass (interfaces/messages.py);
- a service: `X.Request`/`X.Response` (rclpy) and `XRequest`/`XResponse` (rospy);
- an action: `X.Goal`/`X.Result`/`X.Feedback` (rclpy) and `XAction`, `XGoal`, ... (actionlib).

A definition also travels as text (`full_text`, with its nested messages'): a program's
advertise_service carries it, and the lab reads it with `carried`.
"""

from __future__ import annotations

import re
import threading
from pathlib import Path
from typing import Any

from interfaces.messages import Message, Stamp
from interfaces.parser import (
    FIELD_LINE,
    MAX_DEFAULT_VALUES,
    MAX_DEFINITION_CHARS,
    MAX_DEFINITION_FIELDS,
    PRIMITIVES,
    DefinitionError,
    parse_fields,
    read_definition,
    sections,
)
from interfaces.sequences import TYPECODES

SHARE = Path(__file__).parent / "share"
SHARE_ROS1 = Path(__file__).parent / "share_ros1"  # ROS 1's own versions (std_msgs/Header with seq), for rospy
KINDS = ("msg", "srv", "action")
# names made of another kind's definition, as genpy and genmsg make them: suffix -> the kind it comes from
DERIVED = {
    "srv": (("Request", "srv"), ("Response", "srv")),
    "msg": (
        ("ActionGoal", "action"),
        ("ActionResult", "action"),
        ("ActionFeedback", "action"),
        ("Action", "action"),
        ("Goal", "action"),
        ("Result", "action"),
        ("Feedback", "action"),
    ),
    "action": (("Goal", "action"), ("Result", "action"), ("Feedback", "action"), ("Action", "action")),
}
# genmsg's messages of an action `X` (actionlib's topics carry them), as its genaction writes them
ACTION_MESSAGES = {
    "ActionGoal": "Header header\nactionlib_msgs/GoalID goal_id\n{name}Goal goal\n",
    "ActionResult": "Header header\nactionlib_msgs/GoalStatus status\n{name}Result result\n",
    "ActionFeedback": "Header header\nactionlib_msgs/GoalStatus status\n{name}Feedback feedback\n",
    "Action": "{name}ActionGoal action_goal\n{name}ActionResult action_result\n{name}ActionFeedback action_feedback\n",
}


class Interfaces:
    """The interface packages of the search roots, loaded on demand (thread-safe, cached)."""

    def __init__(
        self,
        roots: list[Path],
        texts: dict[tuple[str, str, str], str] | None = None,
    ) -> None:
        self.roots = [Path(r) for r in roots] + [SHARE]
        self.texts = dict(texts or {})  # (package, kind, name) -> text carried by a client: before the roots
        self._cache: dict[tuple[str, str, str], Any] = {}
        self._making: list[tuple[str, str, str]] = []  # the definitions being made now: a type met again is recursive
        self._lock = threading.RLock()
        self.named: dict[str, Path] = {}  # a workspace's packages by their package.xml names (rosclient/packages.py)

    def use_ros1(self) -> None:
        """ROS 1's versions of the standard messages first (rospy's import: a Header with `seq`); the
        classes made before keep their definitions."""
        if SHARE_ROS1 not in self.roots:
            self.roots.insert(self.roots.index(SHARE), SHARE_ROS1)

    def package_dirs(self, package: str) -> list[Path]:
        named = [self.named[package]] if package in self.named else []
        return [d for d in [*named, *(r / package for r in self.roots)] if any((d / k).is_dir() for k in KINDS)]

    def is_package(self, package: str) -> bool:
        return any(p == package for p, _, _ in self.texts) or bool(self.package_dirs(package))

    def available(self, kind: str) -> dict[str, list[str]]:
        """Every package of the roots with definitions of `kind` -> their names, sorted (rosidl_runtime_py's
        get_message_interfaces and the like, for `interface list`); a name in two roots once."""
        found: dict[str, set[str]] = {}
        for root in self.roots:
            for definition in root.glob(f"*/{kind}/*.{kind}"):
                found.setdefault(definition.parent.parent.name, set()).add(definition.stem)
        return {package: sorted(names) for package, names in sorted(found.items())}

    def find(self, package: str, kind: str, name: str) -> Path | None:
        if (package, kind, name) in self.texts:
            return Path(f"<the definition of {package}/{kind}/{name} it carried>")
        for directory in self.package_dirs(package):
            candidate = directory / kind / f"{name}.{kind}"
            if candidate.is_file():
                return candidate
        return None

    def names(self, package: str, kind: str) -> list[str]:
        """What `from package.kind import *` gives, as genpy's modules export it: each definition's
        class and the classes made of it (a service's XRequest, XResponse; an action's XAction,
        XActionGoal, ..., XGoal, XResult, XFeedback in `.msg` too)."""
        found: set[str] = set()
        for directory in self.package_dirs(package):
            found.update(p.stem for p in (directory / kind).glob(f"*.{kind}"))
        for suffix, source in DERIVED[kind]:
            for directory in self.package_dirs(package):
                found.update(p.stem + suffix for p in (directory / source).glob(f"*.{source}"))
        found.update(n for p, k, n in self.texts if p == package and k == kind)
        return sorted(found)

    def derived(self, package: str, kind: str, name: str) -> Any:
        """The class genpy/genmsg make under `name` of another definition (None: none is made so)."""
        for suffix, source in DERIVED[kind]:
            stem = name[: -len(suffix)]
            if not (name.endswith(suffix) and stem) or self.find(package, source, stem) is None:
                continue
            made = self.get(package, source, stem)
            if source == "srv" or suffix in ("Goal", "Result", "Feedback"):
                return getattr(made, suffix)
            if kind != "msg":  # XAction in `.action` is the message of `.msg`
                return self.get(package, "msg", name)
            text = ACTION_MESSAGES[suffix].format(name=stem)
            where = Path(f"<{package}/{name}, made of {package}/action/{stem}.action as genmsg makes it>")
            message = self._message(package, name, (text, 1), where, f"{package}/{name}", f"{package}/msg/{name}")
            if suffix == "Action":  # actionlib's ActionSpec: its parts by name too
                for part in ("Goal", "Result", "Feedback"):
                    setattr(message, part, getattr(made, part))
                for part in ("ActionGoal", "ActionResult", "ActionFeedback"):
                    setattr(message, part, self.get(package, "msg", stem + part))
                spec: Any = message  # a message class that is also actionlib's ActionSpec
                spec._action_type = made._ros2_type
            return message
        return None

    def get(self, package: str, kind: str, name: str) -> Any:
        with self._lock:
            key = (package, kind, name)
            if key not in self._cache:
                path = self.find(package, kind, name)
                made = self.derived(package, kind, name) if path is None else None
                if made is not None:
                    self._cache[key] = made
                    return made
                if path is None:
                    searched = ", ".join(str(r / package / kind / f"{name}.{kind}") for r in self.roots)
                    raise DefinitionError(
                        f"cannot import name '{name}' from '{package}.{kind}': no definition file "
                        f"(looked for {searched})",
                        name=f"{package}.{kind}",
                    )
                if key in self._making:
                    cycle = " -> ".join(f"{p}/{n}" for p, _, n in self._making[self._making.index(key) :])
                    raise DefinitionError(
                        f"{path}: {package}/{name} contains itself ({cycle} -> {package}/{name}): a recursive "
                        "message type has no end (ROS refuses it too)",
                        name=f"{package}.{kind}",
                    )
                self._making.append(key)
                try:
                    self._cache[key] = self._make(package, kind, name, path)
                finally:
                    self._making.pop()
            return self._cache[key]

    def message(self, type_name: str) -> type[Message]:
        """The class of 'pkg/Name' or 'pkg/msg/Name'."""
        parts = type_name.strip("/").split("/")
        if len(parts) not in (2, 3):
            raise DefinitionError(f"not a message type: {type_name!r} (expected PACKAGE/Name)")
        return self.get(parts[0], "msg", parts[-1])

    def _make(self, package: str, kind: str, name: str, path: Path) -> Any:
        if (package, kind, name) in self.texts:
            text = self.texts[package, kind, name]
        else:
            text = read_definition(path, f"{package}.{kind}")
        if len(text) > MAX_DEFINITION_CHARS:
            raise DefinitionError(
                f"{path}: {len(text)} characters, at most {MAX_DEFINITION_CHARS} in a definition",
                name=f"{package}.{kind}",
            )
        parts_text = sections(text)
        wanted = {"msg": 1, "srv": 2, "action": 3}[kind]
        if len(parts_text) != wanted:
            raise DefinitionError(
                f"{path}: expected {wanted} section{'s' if wanted > 1 else ''} separated by "
                f"'---' lines, found {len(parts_text)}",
                name=f"{package}.{kind}",
            )
        if kind == "msg":
            return self._message(package, name, parts_text[0], path, f"{package}/{name}", f"{package}/msg/{name}")
        suffixes = ("Request", "Response") if kind == "srv" else ("Goal", "Result", "Feedback")
        parts = [
            self._message(package, name + s, section, path, f"{package}/{name}{s}", f"{package}/{kind}/{name}_{s}")
            for s, section in zip(suffixes, parts_text)
        ]
        namespace: dict[str, Any] = {s: cls for s, cls in zip(suffixes, parts)}
        namespace.update(
            _type=f"{package}/{name}",
            _ros2_type=f"{package}/{kind}/{name}",
            _definition=text,
            __module__=f"{package}.{kind}",
        )
        if kind == "srv":
            namespace.update(_request_class=parts[0], _response_class=parts[1])
        else:
            namespace.update(_action_type=f"{package}/{kind}/{name}")
        return type(name, (), namespace)

    def _message(
        self, package: str, name: str, section: tuple[str, int], path: Path, type_name: str, ros2_type: str
    ) -> type[Message]:
        text, first = section
        fields, constants = parse_fields(text, path, package, first)
        for f in fields:
            scalar = f.base.split("<=")[0]
            if scalar not in PRIMITIVES:
                try:
                    f.msg_class = self.message(scalar)
                except DefinitionError as exc:
                    raise DefinitionError(
                        f"{f.line}: field '{f.name}' has type {f.base}, whose definition cannot be read: {exc}",
                        name=package,
                    ) from None
        values = 0  # what the message's default holds (Field.zero builds it): capped, nesting counted
        for f in fields:
            one = f.msg_class._default_values if f.msg_class is not None else 1
            if f.array is None:  # noqa: SIM108 - three cases read better as branches
                count = one
            else:  # a variable-length or bounded array's default is empty
                count = 0 if f.array is True or f.bound else f.array * one
            values += count
            if values > MAX_DEFAULT_VALUES:
                raise DefinitionError(
                    f"{f.line}: the default of {type_name} would hold more than {MAX_DEFAULT_VALUES} values "
                    f"(field '{f.name}', {f.type_text}: {count}); use a variable-length array (T[])",
                    name=package,
                )
        namespace: dict[str, Any] = {
            "__slots__": tuple(f.attr for f in fields),
            "_type": type_name,
            "_ros2_type": ros2_type,
            "_fields": tuple(fields),
            "_definition": text,
            "_default_values": values,
            "_numeric": {f.attr: f for f in fields if f.array is not None and f.base in TYPECODES},
            "__slots__types": [f.type_text for f in fields],
            "__module__": f"{package}.msg",
        }
        namespace.update(constants)
        base: tuple[type, ...] = (Message,)
        if type_name in ("builtin_interfaces/Time", "builtin_interfaces/Duration"):
            base = (Stamp, Message)
        return type(name, base, namespace)


SEPARATOR = "=" * 80
_MSG_HEADER = re.compile(r"^=+[ \t]*\n+MSG:[ \t]*(\S+)[ \t]*$", re.MULTILINE)


def full_text(interface: Any) -> str:
    """The definition of a service/action/message class with every nested message's after it, in
    the format of ROS 1's message_definition and bag files (`====...` then `MSG: pkg/Name`)."""
    parts, seen = [interface._definition.rstrip("\n")], set()
    pending = [getattr(interface, attr) for attr in ("_request_class", "_response_class") if hasattr(interface, attr)]
    pending += [interface] if hasattr(interface, "_fields") else []
    pending += [getattr(interface, s) for s in ("Goal", "Result", "Feedback") if hasattr(interface, s)]
    while pending:
        for f in pending.pop(0)._fields:
            nested = f.msg_class
            if nested is not None and nested._type not in seen:
                seen.add(nested._type)
                parts.append(f"{SEPARATOR}\nMSG: {nested._type}\n{nested._definition.rstrip(chr(10))}")
                pending.append(nested)
    text = "\n".join(parts) + "\n"
    if len(text) > MAX_DEFINITION_CHARS:  # refused here, before it is sent: the lab would refuse it
        raise DefinitionError(
            f"the definition of {interface._type} with its nested messages' is {len(text)} characters, "
            f"at most {MAX_DEFINITION_CHARS}",
            name=interface._type,
        )
    return text


def field_count(text: str) -> int:
    """The fields of a carried text (`full_text`'s: each type once): its lines that declare a field
    (not a constant, a comment, a blank line, a section's `---` or a `MSG:` line), without parsing it."""
    count = 0
    for raw in text.splitlines():
        match = FIELD_LINE.match(raw.strip())
        if match is not None and not match[6] and not raw.lstrip().startswith("MSG:"):
            count += 1
    return count


def carried(type_name: str, kind: str, text: str) -> tuple[Interfaces, tuple[str, str]]:
    """Interfaces that know a client's carried `text` (from `full_text`) for `type_name` of `kind`,
    and (package, name) of the type: `.get(package, kind, name)` makes its classes."""
    parts = type_name.strip("/").split("/")
    if len(parts) not in (2, 3) or not all(re.fullmatch(r"[A-Za-z]\w*", p) for p in parts):
        raise DefinitionError(f"not a type name: {type_name!r} (expected PACKAGE/Name or PACKAGE/{kind}/Name)")
    package, name = parts[0], parts[-1]
    count = field_count(text)
    if count > MAX_DEFINITION_FIELDS:  # counted before any class or model is made of it
        raise DefinitionError(
            f"it has {count} fields, over the cap of {MAX_DEFINITION_FIELDS} (its types' fields counted once each)",
            name=type_name,
        )
    pieces = _MSG_HEADER.split(text)
    texts = {(package, kind, name): pieces[0]}
    for nested, body in zip(pieces[1::2], pieces[2::2]):
        nested_parts = nested.strip("/").split("/")
        if len(nested_parts) not in (2, 3):
            raise DefinitionError(f"{type_name}: 'MSG: {nested}' is not a message type name (expected PACKAGE/Name)")
        texts[nested_parts[0], "msg", nested_parts[-1]] = body.strip("\n")
    return Interfaces([], texts), (package, name)
