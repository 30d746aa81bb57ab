"""ROS interfaces from their text, as genpy (ROS 1) and rosidl_generator_py (ROS 2) make them.

`from <pkg>.msg import X` (and `.srv`, `.action`) finds `<pkg>/msg/X.msg` in the search roots — the
student's workspace (the program's folder and its parents, or `--workspace DIR`) first, then the
definitions this package ships (app/rosclient/share: the standard packages and the lab's hri_lab) —
parses it and makes a class:

- a message: typed fields with ROS defaults (0, 0.0, False, '', [], a nested message), constants as
  class attributes, construction by keyword (rclpy, rospy) or by position (rospy), `_type`,
  `get_fields_and_field_types()`; `to_json`/`from_json` for rosbridge's JSON;
- a service: `X.Request`/`X.Response` (rclpy) and `XRequest`/`XResponse` (rospy);
- an action: `X.Goal`/`X.Result`/`X.Feedback` (rclpy) and `XAction`, `XGoal`, `XResult`, `XFeedback`
  (actionlib).

A missing or malformed definition is an ImportError naming the file, the line and what was expected;
so is one beyond the caps below (a file's size, a fixed array's length, the values of a message's
default, a recursive type), which hold wherever a definition is read: in a program and in the lab.
"""

from __future__ import annotations

import base64
import importlib.abc
import importlib.machinery
import keyword
import re
import sys
import threading
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

SHARE = Path(__file__).parent / "share"
KINDS = ("msg", "srv", "action")

INTEGERS = {
    "byte": (0, 255),
    "char": (0, 255),
    "int8": (-(2**7), 2**7 - 1),
    "uint8": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
    "uint64": (0, 2**64 - 1),
}
FLOATS = ("float32", "float64")
PRIMITIVES = {*INTEGERS, *FLOATS, "bool", "string", "wstring"}
BUILTIN_ALIASES = {
    "time": "builtin_interfaces/Time",
    "duration": "builtin_interfaces/Duration",
    "Header": "std_msgs/Header",
}
BYTES = ("uint8", "byte", "char")  # arrays of these travel as base64 text in rosbridge's JSON
MAX_DEFINITION_CHARS = 65_536  # characters of one definition's text (a file, or a type a client carries)
MAX_FIXED_ARRAY = 65_536  # items of a fixed-size array (T[N]); a bound (T[<=N], string<=N) has at most 9 digits
MAX_DEFAULT_VALUES = 65_536  # values a message's default holds, nested messages' and fixed arrays' items counted
_FIELD = re.compile(r"^([A-Za-z][\w/]*(?:<=\d+)?)(\[(<=)?(\d*)\])?\s+([A-Za-z]\w*)\s*(=)?\s*(.*)$")


LAB_PACKAGE = "hri_lab"  # its .srv/.action texts are the lab's own declarations (app/rosclient/lab_package.py)


class DefinitionError(ImportError):
    """A definition that cannot be read: names the file, the line and what was expected."""


class Field:
    __slots__ = ("name", "attr", "base", "array", "bound", "default", "msg_class", "line")

    def __init__(self, name: str, base: str, array: int | None | bool, bound: bool, default: Any) -> None:
        self.name = name  # the wire name
        self.attr = name + "_" if keyword.iskeyword(name) else name  # genpy's rule for keywords
        self.base, self.array, self.bound, self.default = base, array, bound, default
        self.msg_class = None  # a nested message's class (resolved after parsing)
        self.line = ""  # "FILE, line N": where it is defined

    @property
    def type_text(self) -> str:
        base = self.base.split("<=")[0] if self.base.startswith(("string<=", "wstring<=")) else self.base
        if self.array is None:
            return base
        return f"{base}[{'<=' if self.bound else ''}{self.array if self.array is not True else ''}]"

    def zero(self) -> Any:
        if self.default is not None:
            return list(self.default) if isinstance(self.default, list) else self.default
        if self.array is not None:
            if self.array is True or self.bound:
                return b"" if self.base in BYTES else []
            return bytes(self.array) if self.base in BYTES else [self._scalar_zero() for _ in range(self.array)]
        return self._scalar_zero()

    def _scalar_zero(self) -> Any:
        if self.msg_class is not None:
            return self.msg_class()
        base = self.base.split("<=")[0]
        if base in INTEGERS:
            return 0
        if base in FLOATS:
            return 0.0
        if base == "bool":
            return False
        return ""


class Message:
    """A message of a parsed definition (subclasses are made by `message_class`)."""

    __slots__ = ()
    _type = ""
    _ros2_type = ""
    _fields: tuple[Field, ...] = ()
    _definition = ""
    _default_values = 0  # values its default holds (capped: MAX_DEFAULT_VALUES)

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        fields = self._fields
        if len(args) > len(fields):
            raise TypeError(
                f"{self._type} takes {len(fields)} field values ({', '.join(f.attr for f in fields)}), got {len(args)}"
            )
        if args and kwargs:
            raise TypeError(f"{self._type}: give the field values by position or by name, not both")
        names = {f.attr: f for f in fields}
        for key in kwargs:
            if key not in names:
                raise TypeError(f"{self._type} has no field '{key}' (its fields: {', '.join(names) or 'none'})")
        for i, f in enumerate(fields):
            if i < len(args):
                value = args[i]
            elif f.attr in kwargs:
                value = kwargs[f.attr]
            else:
                value = f.zero()
            object.__setattr__(self, f.attr, value)

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        return {f.attr: f.type_text for f in cls._fields}

    @property
    def __slots_types__(self):  # pragma: no cover - genpy compatibility only
        return [f.type_text for f in self._fields]

    def __eq__(self, other: Any) -> bool:
        return type(other) is type(self) and all(getattr(self, f.attr) == getattr(other, f.attr) for f in self._fields)

    def __repr__(self) -> str:
        pkg, _, name = self._type.partition("/")
        inner = ", ".join(f"{f.attr}={getattr(self, f.attr)!r}" for f in self._fields)
        return f"{pkg}.msg.{name}({inner})"

    __str__ = __repr__

    # --- rosbridge JSON -------------------------------------------------------------------------
    def to_json(self) -> dict:
        return {f.name: _to_json(self._type, f, getattr(self, f.attr)) for f in self._fields}

    @classmethod
    def from_json(cls, data: Any) -> Message:
        if not isinstance(data, dict):
            raise TypeError(f"{cls._type}: expected a JSON object, got {type(data).__name__}")
        out = cls()
        for f in cls._fields:
            if f.name in data and data[f.name] is not None:
                object.__setattr__(out, f.attr, _from_json(f, data[f.name]))
        return out


def _to_json(owner: str, f: Field, value: Any) -> Any:
    where = f"{owner}.{f.attr}"
    if f.array is not None:
        if f.base in BYTES and isinstance(value, (bytes, bytearray, memoryview)):
            return base64.b64encode(bytes(value)).decode("ascii")
        if hasattr(value, "tolist") and not isinstance(value, (list, tuple)):
            value = value.tolist()
        if not isinstance(value, (list, tuple)):
            raise TypeError(
                f"The '{f.attr}' field of {owner} must be a sequence ({f.type_text}), got {type(value).__name__}"
            )
        if f.array is not True and not f.bound and len(value) != f.array:
            raise ValueError(f"The '{f.attr}' field of {owner} must have {f.array} elements, got {len(value)}")
        if f.bound and len(value) > f.array:
            raise ValueError(f"The '{f.attr}' field of {owner} must have at most {f.array} elements, got {len(value)}")
        return [_scalar_json(where, f, v) for v in value]
    return _scalar_json(where, f, value)


def _scalar_json(where: str, f: Field, value: Any) -> Any:
    if f.msg_class is not None:
        if isinstance(value, Message):
            return value.to_json()
        if f.msg_class._type in ("builtin_interfaces/Time", "builtin_interfaces/Duration") and hasattr(value, "secs"):
            return {"sec": int(value.secs), "nanosec": int(value.nsecs)}  # a rospy.Time/Duration
        if isinstance(value, dict):
            return f.msg_class.from_json(value).to_json()
        raise TypeError(f"The '{where}' field must be a {f.msg_class._type}, got {type(value).__name__}")
    base = f.base.split("<=")[0]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()  # a numpy scalar
    if base in INTEGERS:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"The '{where}' field must be of type 'int' ({f.base}), got {value!r}")
        low, high = INTEGERS[base]
        if not low <= value <= high:
            raise ValueError(f"The '{where}' field must be an integer in [{low}, {high}] ({f.base}), got {value}")
        return value
    if base in FLOATS:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"The '{where}' field must be of type 'float' ({f.base}), got {value!r}")
        return float(value)
    if base == "bool":
        if not isinstance(value, bool):
            raise TypeError(f"The '{where}' field must be of type 'bool', got {value!r}")
        return value
    if not isinstance(value, str):
        raise TypeError(f"The '{where}' field must be of type 'str' ({f.base}), got {value!r}")
    return value


def _from_json(f: Field, value: Any) -> Any:
    if f.array is not None:
        if f.base in BYTES and isinstance(value, str):
            return base64.b64decode(value)
        if f.base in BYTES and isinstance(value, list):
            return bytes(value)
        return [_scalar_from_json(f, v) for v in value]
    return _scalar_from_json(f, value)


def _scalar_from_json(f: Field, value: Any) -> Any:
    if f.msg_class is not None:
        if isinstance(value, dict) and f.msg_class._type in ("builtin_interfaces/Time", "builtin_interfaces/Duration"):
            value = {
                "sec": value.get("sec", value.get("secs", 0)),
                "nanosec": value.get("nanosec", value.get("nsecs", 0)),
            }
        return f.msg_class.from_json(value)
    base = f.base.split("<=")[0]
    if base in FLOATS and isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    return value


# --- parsing ------------------------------------------------------------------------------------
def parse_fields(text: str, path: Path, package: str, first_line: int = 1) -> tuple[list[Field], dict[str, Any]]:
    """The fields and constants of one message definition (a section of a .srv/.action)."""
    fields: list[Field] = []
    constants: dict[str, Any] = {}
    for number, raw in enumerate(text.splitlines(), first_line):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        where = f"{path}, line {number}"
        is_string = line.split()[0] in ("string", "wstring") or line.split()[0].startswith(("string<=", "wstring<="))
        if not (is_string and "=" in line):
            line = line.split("#", 1)[0].strip()
        m = _FIELD.match(line)
        if m is None:
            raise DefinitionError(
                f"{where}: expected 'TYPE NAME', 'TYPE NAME DEFAULT' or 'TYPE NAME=VALUE' "
                f"(e.g. 'int64 a'), got {raw.strip()!r}",
                name=package,
            )
        base, brackets, bounded, size, name, is_constant, rest = m.groups()
        if name in {f.name for f in fields} or name in constants:
            raise DefinitionError(f"{where}: field '{name}' is defined twice", name=package)
        array: int | None | bool = None
        for number_text in (size or "", base.partition("<=")[2]):
            if len(number_text) > 9:
                raise DefinitionError(
                    f"{where}: a size or bound of at most 9 digits, got {len(number_text)}", name=package
                )
        if brackets:
            array = int(size) if size else True
            if bounded and not size:
                raise DefinitionError(f"{where}: expected a bound after '<=' in {brackets!r}", name=package)
            if not bounded and size and int(size) > MAX_FIXED_ARRAY:
                raise DefinitionError(
                    f"{where}: a fixed-size array of at most {MAX_FIXED_ARRAY} items, got {int(size)} "
                    "(a variable-length T[] holds any number)",
                    name=package,
                )
        base = _qualify(base, package)
        scalar = base.split("<=")[0]
        if scalar not in PRIMITIVES and "/" not in scalar:
            raise DefinitionError(
                f"{where}: unknown type {base!r}: expected a primitive (bool, int8..uint64, float32, "
                f"float64, string, time, duration) or PACKAGE/Message",
                name=package,
            )
        if is_constant:
            if array is not None or scalar not in PRIMITIVES:
                raise DefinitionError(f"{where}: a constant must be of a primitive type, not {base}", name=package)
            constants[name] = _literal(scalar, rest.strip(), where, package)
            continue
        default = None
        rest = rest.strip()
        if rest:
            if scalar not in PRIMITIVES:
                raise DefinitionError(
                    f"{where}: a default value is only allowed for primitive types, not {base}", name=package
                )
            if array is not None:
                items = rest.strip()
                if not (items.startswith("[") and items.endswith("]")):
                    raise DefinitionError(
                        f"{where}: expected an array default like [1, 2, 3], got {rest!r}", name=package
                    )
                default = [_literal(scalar, x.strip(), where, package) for x in items[1:-1].split(",") if x.strip()]
            else:
                default = _literal(scalar, rest, where, package)
        fields.append(Field(name, base, array, bool(bounded), default))
        fields[-1].line = where
    return fields, constants


def _qualify(base: str, package: str) -> str:
    if base in BUILTIN_ALIASES:
        return BUILTIN_ALIASES[base]
    parts = base.split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return f"{parts[0]}/{parts[2]}"
    if len(parts) == 1 and base.split("<=")[0] not in PRIMITIVES:
        return f"{package}/{base}"
    return base


def _literal(scalar: str, text: str, where: str, package: str) -> Any:
    try:
        if scalar in INTEGERS:
            value, (low, high) = int(text, 0), INTEGERS[scalar]
            if not low <= value <= high:
                raise DefinitionError(f"{where}: {text} is out of {scalar}'s range [{low}, {high}]", name=package)
            return value
        if scalar in FLOATS:
            return float(text)
        if scalar == "bool":
            if text.lower() in ("true", "1"):
                return True
            if text.lower() in ("false", "0"):
                return False
            raise ValueError(text)
        if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
            return text[1:-1]
        return text
    except ValueError:
        raise DefinitionError(f"{where}: expected a {scalar} value, got {text!r}", name=package) from None


# --- loading ------------------------------------------------------------------------------------
class Interfaces:
    """The interface packages of the search roots, loaded on demand (thread-safe, cached)."""

    def __init__(
        self,
        roots: list[Path],
        texts: dict[tuple[str, str, str], str] | None = None,
        lab: Callable[[], dict[str, dict[str, str]]] | None = None,
    ) -> None:
        self.roots = [Path(r) for r in roots] + [SHARE]
        self.texts = dict(texts or {})  # (package, kind, name) -> text carried by a client: before the roots
        self._lab_source, self._lab = lab, None  # the lab's own package, LAB_PACKAGE: after the roots
        self._cache: dict[tuple[str, str, str], Any] = {}
        self._making: list[tuple[str, str, str]] = []  # the definitions being made now: a type met again is recursive
        self._lock = threading.RLock()

    @property
    def lab(self) -> dict[str, dict[str, str]]:
        """kind -> name -> text of the lab's own package, read when first asked for (it imports the lab's declarations)."""
        if self._lab is None:
            self._lab = self._lab_source() if self._lab_source else {}
        return self._lab

    def package_dirs(self, package: str) -> list[Path]:
        return [r / package for r in self.roots if any((r / package / k).is_dir() for k in KINDS)]

    def is_package(self, package: str) -> bool:
        return (
            (package == LAB_PACKAGE and self._lab_source is not None)
            or any(p == package for p, _, _ in self.texts)
            or bool(self.package_dirs(package))
        )

    def find(self, package: str, kind: str, name: str) -> Path | None:
        if (package, kind, name) in self.texts:
            return Path(f"<the definition of {package}/{kind}/{name} it carried>")
        for directory in self.package_dirs(package):
            candidate = directory / kind / f"{name}.{kind}"
            if candidate.is_file():
                return candidate
        if package == LAB_PACKAGE and name in self.lab.get(kind, {}):
            return Path(f"<the lab's declaration of {LAB_PACKAGE}/{kind}/{name}>")
        return None

    def names(self, package: str, kind: str) -> list[str]:
        found = set(self.lab.get(kind, {})) if package == LAB_PACKAGE else set()
        for directory in self.package_dirs(package):
            found.update(p.stem for p in (directory / kind).glob(f"*.{kind}"))
        return sorted(found)

    def get(self, package: str, kind: str, name: str) -> Any:
        with self._lock:
            key = (package, kind, name)
            if key not in self._cache:
                path = self.find(package, kind, name)
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
        elif str(path).startswith("<"):
            text = self.lab[kind][name]
        else:
            text = _read_definition(path, f"{package}.{kind}")
        if len(text) > MAX_DEFINITION_CHARS:
            raise DefinitionError(
                f"{path}: {len(text)} characters, at most {MAX_DEFINITION_CHARS} in a definition",
                name=f"{package}.{kind}",
            )
        sections = _sections(text)
        wanted = {"msg": 1, "srv": 2, "action": 3}[kind]
        if len(sections) != wanted:
            raise DefinitionError(
                f"{path}: expected {wanted} section{'s' if wanted > 1 else ''} separated by "
                f"'---' lines, found {len(sections)}",
                name=f"{package}.{kind}",
            )
        if kind == "msg":
            return self._message(package, name, sections[0], path, f"{package}/{name}", f"{package}/msg/{name}")
        suffixes = ("Request", "Response") if kind == "srv" else ("Goal", "Result", "Feedback")
        parts = [
            self._message(package, name + s, section, path, f"{package}/{name}{s}", f"{package}/{kind}/{name}_{s}")
            for s, section in zip(suffixes, sections)
        ]
        namespace = {s: cls for s, cls in zip(suffixes, parts)}
        namespace.update(
            _type=f"{package}/{name}",
            _ros2_type=f"{package}/{kind}/{name}",
            _definition=text,
            __module__=f"{package}.{kind}",
        )
        if kind == "srv":
            namespace.update(_request_class=parts[0], _response_class=parts[1])
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
            if f.array is None:
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
            "__slots__types": [f.type_text for f in fields],
            "__module__": f"{package}.msg",
        }
        namespace.update(constants)
        base: tuple[type, ...] = (Message,)
        if type_name in ("builtin_interfaces/Time", "builtin_interfaces/Duration"):
            base = (_Stamp, Message)
        return type(name, base, namespace)


def _read_definition(path: Path, name: str) -> str:
    """A definition file's text; not UTF-8 is a DefinitionError naming the line."""
    with path.open("rb") as handle:
        data = handle.read(MAX_DEFINITION_CHARS * 4 + 1)  # UTF-8 takes at most 4 bytes a character
    if len(data) > MAX_DEFINITION_CHARS * 4:
        raise DefinitionError(f"{path}: more than {MAX_DEFINITION_CHARS} characters in a definition", name=name)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise DefinitionError(f"{path}, line {line}: not UTF-8 text (byte {exc.start})", name=name) from None


class _Stamp:
    """builtin_interfaces/Time and Duration also answer rospy's Time API (secs, nsecs, to_sec)."""

    __slots__ = ()

    @property
    def secs(self) -> int:
        return self.sec

    @property
    def nsecs(self) -> int:
        return self.nanosec

    def to_sec(self) -> float:
        return self.sec + self.nanosec * 1e-9

    def to_nsec(self) -> int:
        return self.sec * 10**9 + self.nanosec


def _sections(text: str) -> list[tuple[str, int]]:
    """The text split at '---' lines, each with the number of its first line."""
    sections, current, first = [], [], 1
    for number, line in enumerate(text.splitlines(), 1):
        if line.strip() == "---":
            sections.append(("\n".join(current), first))
            current, first = [], number + 1
        else:
            current.append(line)
    sections.append(("\n".join(current), first))
    return sections


# --- carried definitions (a service's text travels with its advertise_service) -------------------
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


def carried(type_name: str, kind: str, text: str) -> tuple[Interfaces, tuple[str, str]]:
    """Interfaces that know a client's carried `text` (from `full_text`) for `type_name` of `kind`,
    and (package, name) of the type: `.get(package, kind, name)` makes its classes."""
    parts = type_name.strip("/").split("/")
    if len(parts) not in (2, 3) or not all(re.fullmatch(r"[A-Za-z]\w*", p) for p in parts):
        raise DefinitionError(f"not a type name: {type_name!r} (expected PACKAGE/Name or PACKAGE/{kind}/Name)")
    package, name = parts[0], parts[-1]
    pieces = _MSG_HEADER.split(text)
    texts = {(package, kind, name): pieces[0]}
    for nested, body in zip(pieces[1::2], pieces[2::2]):
        nested_parts = nested.strip("/").split("/")
        if len(nested_parts) not in (2, 3):
            raise DefinitionError(f"{type_name}: 'MSG: {nested}' is not a message type name (expected PACKAGE/Name)")
        texts[nested_parts[0], "msg", nested_parts[-1]] = body.strip("\n")
    return Interfaces([], texts), (package, name)


# --- imports ------------------------------------------------------------------------------------
class _KindModule(types.ModuleType):
    """`<pkg>.msg` / `.srv` / `.action`: its classes made when first named."""

    def __init__(self, name: str, interfaces: Interfaces, package: str, kind: str) -> None:
        super().__init__(name)
        self._interfaces, self._package, self._kind = interfaces, package, kind

    @property
    def __all__(self) -> list[str]:
        return self._interfaces.names(self._package, self._kind)

    def __getattr__(self, attr: str) -> Any:
        if attr.startswith("__"):
            raise AttributeError(attr)
        interfaces, package, kind = self._interfaces, self._package, self._kind
        if interfaces.find(package, kind, attr) is None:
            # rospy's XRequest/XResponse; actionlib's XAction/XGoal/XResult/XFeedback (in .action and, as
            # genmsg makes them, in .msg)
            for suffix, source in {
                "srv": (("Request", "srv"), ("Response", "srv")),
                "action": (("Goal", "action"), ("Result", "action"), ("Feedback", "action"), ("Action", "action")),
                "msg": (("Goal", "action"), ("Result", "action"), ("Feedback", "action"), ("Action", "action")),
            }[kind]:
                stem = attr[: -len(suffix)]
                if attr.endswith(suffix) and stem and interfaces.find(package, source, stem) is not None:
                    made = interfaces.get(package, source, stem)
                    value = made if suffix == "Action" else getattr(made, suffix)
                    setattr(self, attr, value)
                    return value
        value = interfaces.get(package, kind, attr)
        setattr(self, attr, value)
        return value


class Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports `<pkg>.msg|srv|action` (and `<pkg>` when nothing else provides it) from definitions."""

    def __init__(self, interfaces: Interfaces) -> None:
        self.interfaces = interfaces

    def find_spec(self, fullname: str, path: Any = None, target: Any = None):
        parts = fullname.split(".")
        if len(parts) == 2 and parts[1] in KINDS and self.interfaces.is_package(parts[0]):
            return importlib.machinery.ModuleSpec(fullname, self, is_package=False)
        if len(parts) == 1 and self.interfaces.is_package(parts[0]):
            spec = importlib.machinery.PathFinder.find_spec(fullname, path)
            if spec is None or spec.origin is None:  # nothing, or a folder without __init__.py
                return importlib.machinery.ModuleSpec(fullname, self, is_package=True)
        return None

    def create_module(self, spec):
        parts = spec.name.split(".")
        if len(parts) == 2:
            return _KindModule(spec.name, self.interfaces, parts[0], parts[1])
        module = types.ModuleType(spec.name)
        module.__path__ = []
        return module

    def exec_module(self, module) -> None:
        return None


def install(roots: list[Path], lab: Callable[[], dict[str, dict[str, str]]] | None = None) -> Interfaces:
    """Put the interface finder first on sys.meta_path (the program's process only); `lab`: the lab's own
    package's texts (app/rosclient/lab_package.py), read on first use."""
    interfaces = Interfaces(roots, lab=lab)
    sys.meta_path.insert(0, Finder(interfaces))
    return interfaces


def workspace_roots(program: Path, workspace: str | None = None) -> list[Path]:
    """Where a program's own interface packages are: --workspace DIR, else its folder and parents
    (and each one's `src/`, as a colcon/catkin workspace keeps them)."""
    if workspace:
        base = Path(workspace).resolve()
        return [base, base / "src"]
    roots = []
    for folder in [program.resolve().parent, *program.resolve().parent.parents]:
        roots.extend([folder, folder / "src"])
    return roots
