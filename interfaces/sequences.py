"""Numeric arrays as rclpy's generated messages hold them (rosidl_generator_py): a sequence
(`T[]`, `T[<=N]`) of a numeric primitive is an `array.array` of its typecode, a fixed-size array
(`T[N]`) a numpy array of its dtype; a list given is converted when set. Only in an rclpy program
(`use_typed()`, on rclpy's import); rospy's stay lists. Byte arrays (`uint8`, `byte`, `char`) stay
`bytes` either way (the lab's image pipeline reads them so)."""

from __future__ import annotations

import array
from typing import Any

TYPECODES = {  # the numeric primitives rclpy holds in typed arrays (its SPECIAL_NESTED_BASIC_TYPES, less uint8)
    "int8": "b",
    "int16": "h",
    "uint16": "H",
    "int32": "i",
    "uint32": "I",
    "int64": "q",
    "uint64": "Q",
    "float32": "f",
    "float64": "d",
}
DTYPES = {"float32": "float32", "float64": "float64", **{k: k for k in TYPECODES if k.startswith(("int", "uint"))}}

typed = [False]  # on in an rclpy program


def use_typed() -> None:
    typed[0] = True


def typecode(base: str, array_size: int | bool | None, bound: bool) -> tuple[str, str] | None:
    """('array', typecode) for a numeric sequence, ('numpy', dtype) for a numeric fixed-size array,
    None for anything else or when typed arrays are off."""
    if not typed[0] or array_size is None or base not in TYPECODES:
        return None
    if array_size is True or bound:
        return ("array", TYPECODES[base])
    return ("numpy", DTYPES[base])


def as_typed(kind: tuple[str, str], values: Any) -> Any:
    """`values` in the typed array `kind` names; given as they are when they cannot be (the message's
    to_json names the field and the reason when it is published)."""
    holder, code = kind
    try:
        if holder == "array":
            if isinstance(values, array.array) and values.typecode == code:
                return values
            return array.array(code, values)
        import numpy

        if isinstance(values, numpy.ndarray) and values.dtype == numpy.dtype(code):
            return values
        return numpy.array(values, dtype=code)
    except (TypeError, ValueError, OverflowError):
        return values
