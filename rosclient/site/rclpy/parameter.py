"""rclpy.parameter.Parameter: a named, typed value (rcl_interfaces/ParameterType)."""
from __future__ import annotations

import array
import math
from enum import Enum
from typing import Any


class Parameter:
    class Type(Enum):
        NOT_SET = 0
        BOOL = 1
        INTEGER = 2
        DOUBLE = 3
        STRING = 4
        BYTE_ARRAY = 5
        BOOL_ARRAY = 6
        INTEGER_ARRAY = 7
        DOUBLE_ARRAY = 8
        STRING_ARRAY = 9

        @classmethod
        def from_parameter_value(cls, value: Any) -> "Parameter.Type":
            if value is None:
                return cls.NOT_SET
            if isinstance(value, bool):
                return cls.BOOL
            if isinstance(value, int):
                return cls.INTEGER
            if isinstance(value, float):
                return cls.DOUBLE
            if isinstance(value, str):
                return cls.STRING
            if isinstance(value, (bytes, bytearray)):
                return cls.BYTE_ARRAY
            if isinstance(value, (list, tuple, array.array)):  # array.array: a ParameterValue's (rclpy's too)
                if value and all(isinstance(v, bool) for v in value):
                    return cls.BOOL_ARRAY
                if value and all(isinstance(v, int) and not isinstance(v, bool) for v in value):
                    return cls.INTEGER_ARRAY
                if value and all(isinstance(v, float) for v in value):
                    return cls.DOUBLE_ARRAY
                if value and all(isinstance(v, str) for v in value):
                    return cls.STRING_ARRAY
                if not value:
                    return cls.STRING_ARRAY
            raise TypeError(f"The given value is not one of the allowed types '{value}'.")

        def check(self, value: Any) -> bool:
            return value is None if self is Parameter.Type.NOT_SET else _matches(self, value)

        @property
        def ros_name(self) -> str:
            """rclcpp's name of the type (its refusal messages): 'double', 'integer', ..."""
            return {0: "not set", 1: "bool", 2: "integer", 3: "double", 4: "string", 5: "byte_array",
                    6: "bool_array", 7: "integer_array", 8: "double_array", 9: "string_array"}[self.value]

    def __init__(self, name: str, type_: "Parameter.Type | None" = None, value: Any = None) -> None:
        if type_ is None:
            type_ = Parameter.Type.from_parameter_value(value)
        if not isinstance(type_, Parameter.Type):
            raise TypeError("type must be an instance of Parameter.Type")
        if value is not None and not _matches(type_, value):
            raise ValueError(f"Type '{type_}' and value '{value}' do not agree")
        self._name, self._type_, self._value = name, type_, value

    @property
    def name(self) -> str:
        return self._name

    @property
    def type_(self) -> "Parameter.Type":
        return self._type_

    @property
    def value(self) -> Any:
        return self._value

    def get_parameter_value(self):
        return to_value_msg(self._type_, self._value)

    def to_parameter_msg(self):
        from rcl_interfaces.msg import Parameter as ParameterMsg

        return ParameterMsg(name=self._name, value=self.get_parameter_value())

    @classmethod
    def from_parameter_msg(cls, msg: Any) -> "Parameter":
        type_ = Parameter.Type(msg.value.type)
        return cls(msg.name, type_, from_value_msg(msg.value))

    def __repr__(self) -> str:
        return f"Parameter(name={self._name!r}, type_={self._type_}, value={self._value!r})"


_FIELDS = {1: "bool_value", 2: "integer_value", 3: "double_value", 4: "string_value", 5: "byte_array_value",
           6: "bool_array_value", 7: "integer_array_value", 8: "double_array_value", 9: "string_array_value"}


def _matches(type_: Parameter.Type, value: Any) -> bool:
    try:
        found = Parameter.Type.from_parameter_value(value)
    except TypeError:
        return False
    return found == type_ or (isinstance(value, (list, tuple, array.array)) and not value and type_.value >= 5)


def to_value_msg(type_: Parameter.Type, value: Any):
    from rcl_interfaces.msg import ParameterValue

    msg = ParameterValue(type=type_.value)
    if type_.value in _FIELDS:
        setattr(msg, _FIELDS[type_.value], list(value) if isinstance(value, tuple) else value)
    return msg


def from_value_msg(msg: Any) -> Any:
    field = _FIELDS.get(msg.type)
    return None if field is None else getattr(msg, field)


def parameter_value_to_python(msg: Any) -> Any:
    return from_value_msg(msg)


def range_refusal(name: str, value: Any, descriptor: Any) -> str:
    """rclcpp's refusal of a value outside the descriptor's range ('' when inside)."""
    if value is None or isinstance(value, bool):
        return ""
    for ranges, kind in ((descriptor.floating_point_range, "floating point"), (descriptor.integer_range, "integer")):
        if not ranges or not isinstance(value, (int, float)):
            continue
        r = ranges[0]
        low, high, step = r.from_value, r.to_value, r.step
        tolerance = 1e-9 * max(1.0, abs(low), abs(high))
        inside = low - tolerance <= value <= high + tolerance
        on_step = (not step or math.isclose(value, high, abs_tol=tolerance)
                   or abs((value - low) / step - round((value - low) / step)) * step <= tolerance)
        if not (inside and on_step):
            return f"Parameter {{{name}}} doesn't comply with {kind} range."
    return ""

