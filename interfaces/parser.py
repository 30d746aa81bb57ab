"""The text of ROS interfaces (.msg, .srv, .action) read as genpy (ROS 1) and rosidl (ROS 2) read it:
each line a field (`TYPE NAME`, `TYPE NAME DEFAULT`) or a constant (`TYPE NAME=VALUE`), sections
split at `---`. A malformed line is a DefinitionError naming the file, the line and what was expected;
so is one beyond the caps below (a file's size, a fixed array's length, the values of a message's
default, a recursive type: interfaces/packages.py), which hold wherever a definition is read: in a
program and in the lab.
"""

from __future__ import annotations

import keyword
import re
from pathlib import Path
from typing import Any

from interfaces.definition_limits import MAX_DEFAULT_VALUES as MAX_DEFAULT_VALUES  # the caps: one source for the
from interfaces.definition_limits import MAX_DEFINITION_CHARS as MAX_DEFINITION_CHARS  # lab's parser and the bags'
from interfaces.definition_limits import MAX_DEFINITION_FIELDS as MAX_DEFINITION_FIELDS
from interfaces.definition_limits import MAX_FIXED_ARRAY as MAX_FIXED_ARRAY
from interfaces.sequences import as_typed, typecode

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
FIELD_LINE = re.compile(r"^([A-Za-z][\w/]*(?:<=\d+)?)(\[(<=)?(\d*)\])?\s+([A-Za-z]\w*)\s*(=)?\s*(.*)$")


Constant = int | float | bool | str  # a constant's or a default's value (a default may be a list of them)


class DefinitionError(ImportError):
    """A definition that cannot be read: names the file, the line and what was expected."""


class Field:
    __slots__ = ("array", "attr", "base", "bound", "default", "line", "msg_class", "name")

    def __init__(
        self, name: str, base: str, array: int | bool | None, bound: bool, default: Constant | list[Constant] | None
    ) -> None:
        self.name = name  # the wire name
        self.attr = name + "_" if keyword.iskeyword(name) else name  # genpy's rule for keywords
        self.base, self.array, self.bound, self.default = base, array, bound, default
        self.msg_class: Any = None  # a nested message's class (resolved after parsing)
        self.line = ""  # "FILE, line N": where it is defined

    @property
    def type_text(self) -> str:
        base = self.base.split("<=")[0] if self.base.startswith(("string<=", "wstring<=")) else self.base
        if self.array is None:
            return base
        return f"{base}[{'<=' if self.bound else ''}{self.array if self.array is not True else ''}]"

    def zero(self) -> object:
        typed = typecode(self.base, self.array, self.bound)  # rclpy's typed numeric arrays (interfaces/sequences.py)
        if typed is not None:
            if self.default is not None:
                return as_typed(typed, self.default)
            length = 0 if self.array is True or self.bound else int(self.array or 0)
            return as_typed(typed, [self._scalar_zero()] * length)
        if self.default is not None:
            return list(self.default) if isinstance(self.default, list) else self.default
        if self.array is not None:
            if self.array is True or self.bound:
                return b"" if self.base in BYTES else []
            return bytes(self.array) if self.base in BYTES else [self._scalar_zero() for _ in range(self.array)]
        return self._scalar_zero()

    def _scalar_zero(self) -> object:
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


def parse_fields(text: str, path: Path, package: str, first_line: int = 1) -> tuple[list[Field], dict[str, Constant]]:
    """The fields and constants of one message definition (a section of a .srv/.action)."""
    fields: list[Field] = []
    constants: dict[str, Constant] = {}
    for number, raw in enumerate(text.splitlines(), first_line):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        where = f"{path}, line {number}"
        line = without_comment(line)
        m = FIELD_LINE.match(line)
        if m is None:
            raise DefinitionError(
                f"{where}: expected 'TYPE NAME', 'TYPE NAME DEFAULT' or 'TYPE NAME=VALUE' "
                f"(e.g. 'int64 a'), got {raw.strip()!r}",
                name=package,
            )
        base, brackets, bounded, size, name, is_constant, rest = m.groups()
        if name in {f.name for f in fields} or name in constants:
            raise DefinitionError(f"{where}: field '{name}' is defined twice", name=package)
        array: int | bool | None = None
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
        base = qualify(base, package)
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
        default: Constant | list[Constant] | None = None
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


def without_comment(line: str) -> str:
    """A definition's line without its comment, as genmsg and rosidl read it: a line ends at its first
    '#', but a string constant's value is all that follows its '=' (genmsg's rule; a line is a constant
    when an '=' comes before any '#': a field's comment may hold one)."""
    line = line.strip()
    code = line.split("#", 1)[0].strip()
    kind = code.split(" ", 1)[0].split("<=")[0]
    return line if kind in ("string", "wstring") and "=" in code else code


def qualify(base: str, package: str) -> str:
    """A field's type as its package names it: `pkg/Name` for a bare message name of `package`, the
    builtin aliases' (`Header`, `time`, `duration`), ROS 2's `pkg/msg/Name` as `pkg/Name`."""
    if base in BUILTIN_ALIASES:
        return BUILTIN_ALIASES[base]
    parts = base.split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return f"{parts[0]}/{parts[2]}"
    if len(parts) == 1 and base.split("<=")[0] not in PRIMITIVES:
        return f"{package}/{base}"
    return base


def _literal(scalar: str, text: str, where: str, package: str) -> Constant:
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


def sections(text: str) -> list[tuple[str, int]]:
    """The text split at '---' lines, each with the number of its first line."""
    sections: list[tuple[str, int]] = []
    current: list[str] = []
    first = 1
    for number, line in enumerate(text.splitlines(), 1):
        if line.strip() == "---":
            sections.append(("\n".join(current), first))
            current, first = [], number + 1
        else:
            current.append(line)
    sections.append(("\n".join(current), first))
    return sections


def read_definition(path: Path, name: str) -> str:
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
