"""A node topic's message made whole before it is relayed, as rosbridge_suite's
rosbridge_library/internal/message_conversion.py (`populate_instance`) makes a ROS message of what a
client publishes: a field left out takes its ROS default, a field the type does not have
(`NonexistentFieldException`) or a value of the wrong type (`FieldTypeMismatchException`) is refused
with the field's name, and every subscriber gets every field (a ROS 1 `SimpleActionServer` reads the
`stamp` of a cancel sent as `{"id": ...}` alone).

The type is the lab's where it ships it (interfaces/share) or the definition its first
publisher carried (a program under `hri-lab run` carries its type's full text); a type the lab does
not know is relayed as it was sent. Defaults come from the parsed definitions (interfaces: one
source). The lab speaks ROS 1's and ROS 2's JSON at once, so a time or duration is read in either
spelling (`sec`/`nanosec`, ROS 1's `secs`/`nsecs`) and one left out is filled in both (as rosapi's
`get_time` answers: app/rosbridge/rosapi.py), and a field ROS 1's version of a standard message has
(std_msgs/Header's `seq`: interfaces/share_ros1) is taken where given, and so is a ROS 1 field
named as ROS 2's in capitals (sensor_msgs/CameraInfo's `D`, `K`, `R`, `P`), kept under its ROS 1 name.

A type's converter is made once (cached); a message is converted once per publish, and the one
result is shared by every subscriber's stream (app/rosbridge/internal/shared.py encodes it once).
"""

from __future__ import annotations

from array import array
from collections import OrderedDict
from collections.abc import Callable
from typing import Any

from interfaces.json_value import JSON
from interfaces.messages import Message
from interfaces.packages import SHARE_ROS1, Interfaces, carried
from interfaces.parser import BYTES, FLOATS, INTEGERS, DefinitionError, Field

STAMPS = ("builtin_interfaces/Time", "builtin_interfaces/Duration")  # `time`, `duration`
SPELLINGS = (("sec", "nanosec"), ("secs", "nsecs"))  # ROS 2's and ROS 1's names of a stamp's parts
# array.array's type codes of the integer types (their ranges are the ROS types' on Linux)
ARRAY_CODES = {"byte": "B", "char": "B", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H"}
ARRAY_CODES.update({"int32": "i", "uint32": "I", "int64": "q", "uint64": "Q"})
BASE64 = (*BYTES, "int8")  # arrays that may travel as base64 text (app/recording/bags.py's to_json)
MAX_TYPES = 256  # converters kept (a type and the definition it was read from)

Convert = Callable[[JSON], JSON]  # a value (None: left out) -> its whole value; raises FieldError


class FieldError(ValueError):
    """A field the type does not have, or a value of the wrong type: `path` names the field from the
    message's root (each level adds its name as the error goes up)."""

    def __init__(self, path: list[str], reason: str) -> None:
        super().__init__(reason)
        self.path, self.reason = path, reason

    def within(self, name: str) -> FieldError:
        self.path.insert(0, name)
        return self

    def describe(self, root_type: str) -> str:
        return f"{root_type} message: field '{'.'.join(self.path)}' {self.reason}"


_JSON_KINDS = {
    dict: "an object",
    list: "an array",
    str: "a string",
    int: "an integer",
    float: "a number",
    bool: "a bool",
}


def _mismatch(expected: str, value: JSON) -> FieldError:
    found = "null" if value is None else f"{_JSON_KINDS.get(type(value), type(value).__name__)} {_short(value)}"
    return FieldError([], f"must be {expected}, got {found}")


def _short(value: JSON) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


_SHIPPED = Interfaces([])  # the lab's shipped definitions (interfaces/share)
_SHIPPED_ROS1 = Interfaces([SHARE_ROS1])  # the same with ROS 1's versions first (std_msgs/Header with seq)


_CONVERTERS: OrderedDict[tuple[str, str], Convert | None] = OrderedDict()  # the newest MAX_TYPES, last used last


def converter(type_name: str, definition: str = "") -> Convert | None:
    """The converter of messages of `type_name` ('pkg/Name' or 'pkg/msg/Name'), read from the
    definition its publisher carried, else from the lab's shipped ones; None: a type the lab does
    not know (its messages are relayed as they come). Made once, kept among the MAX_TYPES last used
    until `forget` (the topic whose publisher brought the definition is gone)."""
    key = (type_name, definition)
    if key in _CONVERTERS:
        _CONVERTERS.move_to_end(key)
        return _CONVERTERS[key]
    made = _CONVERTERS[key] = _converter(type_name, definition)
    if len(_CONVERTERS) > MAX_TYPES:
        _CONVERTERS.popitem(last=False)
    return made


def forget(type_name: str, definition: str) -> None:
    """A definition a client brought is no longer any topic's: its converter goes (its memory with it)."""
    if definition:
        _CONVERTERS.pop((type_name, definition), None)


def _converter(type_name: str, definition: str) -> Convert | None:
    try:
        if definition:
            interfaces, (package, name) = carried(type_name, "msg", definition)
            cls = interfaces.get(package, "msg", name)
        else:
            cls = _SHIPPED.message(type_name)
    except DefinitionError:
        return None
    return _message(cls, {})


def populate(type_name: str, definition: str, message: dict) -> dict:
    """`message` whole (every field, defaults where left out), or itself for a type the lab does not
    know; FieldError (its `describe`) names a field the type does not have or a wrong value."""
    convert = converter(type_name, definition)
    if convert is None:
        return message
    whole = convert(message)
    assert isinstance(whole, dict)  # a message's converter makes an object
    return whole


def _ros1_extras(cls: type[Message]) -> dict[str, Field]:
    """The fields ROS 1's version of a standard message has beyond this one (Header's `seq`)."""
    package, _, name = cls._type.partition("/")
    if not (SHARE_ROS1 / package / "msg" / f"{name}.msg").is_file():
        return {}
    ros1 = _SHIPPED_ROS1.message(cls._type)
    own = {f.name for f in cls._fields}
    return {f.name: f for f in ros1._fields if f.name not in own}


def _message(cls: type[Message], made: dict[str, Convert]) -> Convert:
    """The converter of a message class (nested ones made once per type)."""
    if cls._type in made:
        return made[cls._type]
    if cls._type in STAMPS:
        made[cls._type] = _stamp(cls)
        return made[cls._type]
    fields: list[tuple[str, Convert]] = []
    type_name = cls._type

    def convert(value: JSON) -> JSON:
        if value is None:
            value = {}
        if not isinstance(value, dict):
            raise _mismatch(f"a {type_name} (an object)", value)
        out: dict[str, JSON] = {}
        get, name = value.get, ""
        try:
            for name, field_convert in fields:
                out[name] = field_convert(get(name))
        except FieldError as error:
            raise error.within(name) from None
        if not value.keys() <= out.keys():  # a field it does not have, or ROS 1's (Header's seq)
            for key in value:
                if key in out:
                    continue
                extra = extras.get(key)
                if extra is None and key.lower() in named and key.lower() not in value:
                    extra = named[key.lower()]  # ROS 1's capital (CameraInfo's D, K, R, P): kept as ROS 1's
                    del out[key.lower()]
                if extra is None:
                    raise FieldError([str(key)], f"does not exist: {type_name} has no field '{key}'")
                if value[key] is not None:
                    try:
                        out[key] = extra(value[key])
                    except FieldError as error:
                        raise error.within(key) from None
        return out

    made[cls._type] = convert  # before its fields: a type met again (none is recursive) finds it
    defaults = cls().to_json()  # the ROS defaults, as the lab's messages make them
    fields.extend((f.name, _field(f, defaults.get(f.name), made)) for f in cls._fields)
    extras = {name: _field(f, None, made) for name, f in _ros1_extras(cls).items()}
    named = dict(fields)
    return convert


def _stamp(cls: type[Message]) -> Convert:
    """A time or duration: given in ROS 2's spelling or ROS 1's (missing parts 0), or left out (both)."""
    limits = [INTEGERS[f.base] for f in cls._fields]  # (sec, nanosec)'s ranges
    expected = f"a {'time' if cls._type.endswith('Time') else 'duration'} {{sec, nanosec}} or {{secs, nsecs}}"

    (low, high), (nano_low, nano_high) = limits

    def convert(value: JSON) -> JSON:
        if value is None or value == {}:
            return {"sec": 0, "nanosec": 0, "secs": 0, "nsecs": 0}
        if not isinstance(value, dict):
            raise _mismatch(expected, value)
        if len(value) == 2:  # the common case, whole in one spelling
            for sec, nanosec in SPELLINGS:
                whole, part = value.get(sec), value.get(nanosec)
                if type(whole) is int and type(part) is int and low <= whole <= high and nano_low <= part <= nano_high:
                    return {sec: whole, nanosec: part}
        out: dict[str, JSON] = {}
        for spelling in SPELLINGS:
            if any(name in value for name in spelling):
                for name, (least, most) in zip(spelling, limits):
                    part = value.get(name, 0)
                    if type(part) is not int or not least <= part <= most:
                        raise _mismatch(f"an integer in [{least}, {most}]", part).within(name)
                    out[name] = part
        for key in value:
            if key not in out:
                raise FieldError([str(key)], f"does not exist: {expected} has no field '{key}'")
        if len(out) == 4 and (out["sec"], out["nanosec"]) != (out["secs"], out["nsecs"]):
            raise FieldError([], f"gives two different times: {_short(value)}")
        return out

    return convert


def _field(f: Field, default: JSON, made: dict[str, Convert]) -> Convert:
    """A field's converter: a value checked (and made whole), or its default when left out."""
    if f.array is None:
        return _scalar(f, default, made)
    element = _scalar(f, None, made)
    size, bound = f.array, f.bound
    expected = f"an array ({f.type_text}){' or base64 text' if f.base in BASE64 else ''}"
    nested = f.msg_class is not None
    fixed_messages = nested and size is not True and not bound  # T[N] of messages: N defaults
    whole = None if nested else _whole_array(f.base)

    def convert(value: JSON) -> JSON:
        if value is None:
            if fixed_messages:
                return [element(None) for _ in range(int(size))]
            return list(default) if isinstance(default, list) else default
        if isinstance(value, str) and f.base in BASE64:
            return value  # rosbridge's base64 text of a uint8/char array (hri-lab bag play's of int8[] too)
        if not isinstance(value, list):
            raise _mismatch(expected, value)
        if size is not True and (len(value) > size if bound else len(value) != size):
            raise FieldError(
                [], f"requires {'at most ' if bound else ''}{size} items ({f.type_text}), got {len(value)}"
            )
        if whole is not None and whole(value):  # a long array of numbers at C speed, kept as it is
            return value
        out = []
        for i, item in enumerate(value):
            try:
                if item is None:  # an item is never left out
                    raise _mismatch(f"of type {f.base}", item)
                out.append(element(item))
            except FieldError as error:
                raise error.within(str(i)) from None
        return out

    return convert


def _whole_array(base: str) -> Callable[[list], bool] | None:
    """A check that passes a whole array of a primitive type with nothing to change (its items all
    of the type, integers in range), or None; an array it does not pass is checked item by item,
    which names the first wrong one."""
    if base in FLOATS:
        return lambda items: all(type(x) is float for x in items)
    if base in ARRAY_CODES:  # array.array checks each item's type and range in C (it takes a bool as 0/1)
        code = ARRAY_CODES[base]

        def integers(items: list) -> bool:
            try:
                array(code, items)
            except (TypeError, OverflowError):
                return False
            return True

        return integers
    return None


def _scalar(f: Field, default: JSON, made: dict[str, Convert]) -> Convert:
    """One value of a field's type: a nested message, an integer in its range, a float (an integer
    taken as one), a bool, a string (its bound); None (left out) is `default`."""
    if f.msg_class is not None:
        return _message(f.msg_class, made)
    base, _, bound_text = f.base.partition("<=")
    if base in FLOATS:
        return _number(base, default)
    expected, check = _check(base, int(bound_text) if bound_text else None)

    def convert(value: JSON) -> JSON:
        if value is None:
            return default
        if not check(value):
            raise _mismatch(expected, value)
        return value

    return convert


def _number(base: str, default: JSON) -> Convert:
    """A float field's value: a float, or an integer sent on as a float (as ROS delivers it)."""
    expected = f"of type {base} (a number)"

    def number(value: JSON) -> JSON:
        if type(value) is float:
            return value
        if type(value) is int:
            return float(value)
        if value is None:
            return default
        raise _mismatch(expected, value)

    return number


def _check(base: str, limit: int | None) -> tuple[str, Callable[[Any], bool]]:
    """What an integer, bool or string field's value must be, and its check."""
    if base in INTEGERS:
        low, high = INTEGERS[base]
        return f"of type {base} (an integer in [{low}, {high}])", lambda v: type(v) is int and low <= v <= high
    if base == "bool":
        return "of type bool (true or false)", lambda v: type(v) is bool
    if limit is None:
        return f"of type {base}", lambda v: type(v) is str
    return f"of type {base} (at most {limit} characters)", lambda v: type(v) is str and len(v) <= limit
