"""The classes of parsed messages: typed fields with ROS defaults, construction by keyword (rclpy,
rospy) or by position (rospy, genpy), and rosbridge's JSON both ways (`to_json`, `from_json`)."""

from __future__ import annotations

import binascii
from typing import ClassVar, cast

import pybase64

from interfaces.json_value import JSON
from interfaces.parser import BYTES, FLOATS, INTEGERS, Field
from interfaces.sequences import as_typed, typecode, typed


class Message:
    """A message of a parsed definition (subclasses are made by `message_class`). As genpy's, it has
    a slot `_connection_header`, set only on a message rospy received (the publisher's connection
    header, rosclient/site/rospy/topics.py): unset, reading it is an AttributeError."""

    __slots__ = ("_connection_header",)
    _type = ""
    _ros2_type = ""
    _fields: tuple[Field, ...] = ()
    _definition = ""
    _default_values = 0  # values its default holds (capped: parser.MAX_DEFAULT_VALUES)
    _numeric: ClassVar[
        dict[str, Field]
    ] = {}  # attr -> its field, the numeric arrays (typed in rclpy: interfaces/sequences.py)

    def __init__(self, *args: object, **kwargs: object) -> None:
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
                value = None
            if value is None:  # genpy: None (by position or by name) is the field's default
                value = f.zero()
            elif typed[0] and f.attr in self._numeric:
                value = _typed(f, value)
            object.__setattr__(self, f.attr, value)

    def __setattr__(self, name: str, value: object) -> None:
        """As rclpy's setters: a numeric array given as a list is held as its typed array."""
        if typed[0]:
            f = self._numeric.get(name)
            if f is not None:
                value = _typed(f, value)
        object.__setattr__(self, name, value)

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        return {f.attr: f.type_text for f in cls._fields}

    @property
    def __slots_types__(self):  # pragma: no cover - genpy compatibility only
        return [f.type_text for f in self._fields]

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and all(
            _same(getattr(self, f.attr), getattr(other, f.attr)) for f in self._fields
        )

    def __repr__(self) -> str:
        pkg, _, name = self._type.partition("/")
        inner = ", ".join(f"{f.attr}={getattr(self, f.attr)!r}" for f in self._fields)
        return f"{pkg}.msg.{name}({inner})"

    __str__ = __repr__

    # rosbridge JSON -------------------------------------------------------------------------
    def to_json(self) -> dict[str, JSON]:
        return {f.name: _to_json(self._type, f, getattr(self, f.attr)) for f in self._fields}

    @classmethod
    def from_json(cls, data: JSON) -> Message:
        if not isinstance(data, dict):
            raise TypeError(f"{cls._type}: expected a JSON object, got {type(data).__name__}")
        out = cls.__new__(cls)  # each field set once: from the data, else its default
        setter = object.__setattr__
        for f in cls._fields:
            value = data.get(f.name)
            setter(out, f.attr, f.zero() if value is None else _from_json(f, value))
        return out


def _typed(f: Field, value: object) -> object:
    kind = typecode(f.base, f.array, f.bound)
    return value if kind is None else as_typed(kind, value)


def _same(a: object, b: object) -> bool:
    """Two field values equal (a numpy array's == is elementwise: equal when every element is)."""
    if hasattr(a, "shape") or hasattr(b, "shape"):
        return type(a) is type(b) and bool(len(a) == len(b) and (a == b).all())  # type: ignore[arg-type,attr-defined]
    return a == b


def _to_json(owner: str, f: Field, value: object) -> JSON:
    where = f"{owner}.{f.attr}"
    if f.array is not None:
        if f.base in BYTES and isinstance(value, (bytes, bytearray, memoryview)):
            return pybase64.b64encode(bytes(value)).decode("ascii")
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


def _scalar_json(where: str, f: Field, value: object) -> JSON:
    if f.msg_class is not None:
        if isinstance(value, Message):
            return value.to_json()
        if f.msg_class._type in ("builtin_interfaces/Time", "builtin_interfaces/Duration") and (
            hasattr(value, "secs") and hasattr(value, "nsecs")
        ):
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


def _from_json(f: Field, value: JSON) -> object:
    if f.array is not None:
        if f.base in BYTES and isinstance(value, str):
            return _bytes_of(value)
        if not isinstance(value, (list, tuple)):  # a tuple: in a dict a Python program gave (_scalar_json)
            raise TypeError(f"The '{f.attr}' field must be a JSON array ({f.type_text}), got {type(value).__name__}")
        if f.base in BYTES:
            if not all(isinstance(v, int) for v in value):
                raise TypeError(f"The '{f.attr}' field must be a list of byte values ({f.type_text})")
            return bytes(cast("list[int]", value))
        values = [_scalar_from_json(f, v) for v in value]
        kind = typecode(f.base, f.array, f.bound)
        return values if kind is None else as_typed(kind, values)
    return _scalar_from_json(f, value)


def _bytes_of(text: str) -> bytes:
    """A byte array's base64 text, as rosbridge's JSON carries it: SIMD-decoded (a 640x480 image in
    0.1 ms, where the standard library takes 5 ms of the callback's thread); text with characters
    outside the alphabet decoded as base64.b64decode does, skipping them."""
    try:
        return pybase64.b64decode(text, validate=True)
    except binascii.Error:
        return pybase64.b64decode(text)


def _scalar_from_json(f: Field, value: JSON) -> object:
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


class Stamp:
    """builtin_interfaces/Time and Duration also answer rospy's Time API (secs, nsecs, to_sec)."""

    __slots__ = ()
    sec: int  # the message's fields (its class's slots)
    nanosec: int

    @property
    def secs(self) -> int:
        return self.sec

    @secs.setter
    def secs(self, value: int) -> None:
        object.__setattr__(self, "sec", value)  # the message class's slot

    @property
    def nsecs(self) -> int:
        return self.nanosec

    @nsecs.setter
    def nsecs(self, value: int) -> None:
        object.__setattr__(self, "nanosec", value)

    def to_sec(self) -> float:
        return self.sec + self.nanosec * 1e-9

    def to_nsec(self) -> int:
        return self.sec * 10**9 + self.nanosec
