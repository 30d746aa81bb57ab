"""app/ros/messages.py: strict ROS field types, the .msg text of a model, the example /docs pre-fills,
and a message built from a client's arguments (an object or a list in field order)."""

from typing import Annotated

import pytest
from pydantic import Field, ValidationError

from app.ros.messages import (
    INT64_MAX,
    BadArguments,
    Bool,
    Float64,
    Float64Array,
    Int64,
    RosMessage,
    RosType,
    String,
    definition,
    example_of,
    message_from_args,
)


class TwoInts(RosMessage):
    a: Int64
    b: Int64


class Wrench(RosMessage):
    force: Annotated[Float64Array, Field(min_length=6, max_length=6)]
    label: String = "flange"
    on: Bool
    gain: Annotated[float, Field(allow_inf_nan=False), RosType("float64", "N/m")]


def test_definition_is_one_typed_line_per_field_with_comments():
    assert definition(TwoInts) == "int64 a\nint64 b"
    assert definition(Wrench) == "float64[] force\nstring label\nbool on\nfloat64 gain  # N/m"


def test_a_field_without_a_ros_type_is_refused():
    class Untyped(RosMessage):
        x: int

    with pytest.raises(TypeError, match=r"Untyped.x has no ROS type"):
        definition(Untyped)


def test_strict_fields_refuse_strings_bools_fractions_and_overflow():
    assert TwoInts.model_validate({"a": 3.0, "b": -2}).a == 3  # JSON's 3.0 is the integer 3
    for bad in ({"a": "3", "b": 0}, {"a": True, "b": 0}, {"a": 3.5, "b": 0}, {"a": INT64_MAX + 1, "b": 0}):
        with pytest.raises(ValidationError):
            TwoInts.model_validate(bad)
    with pytest.raises(ValidationError):
        TwoInts.model_validate({"a": 1, "b": 2, "c": 3})  # an unknown field


def test_floats_are_finite():
    class Gain(RosMessage):
        k: Float64

    with pytest.raises(ValidationError):
        Gain.model_validate({"k": float("nan")})
    assert Gain.model_validate({"k": 2}).k == 2.0


def test_the_example_is_accepted_and_fills_arrays_to_their_minimum_length():
    example = example_of(Wrench)
    assert example == {"force": [0.0] * 6, "label": "flange", "on": False, "gain": 0.0}
    Wrench.model_validate(example)
    assert example_of(TwoInts) == {"a": 0, "b": 0}  # Int64's declared example


def test_message_from_args_takes_an_object_a_list_in_order_or_nothing():
    assert message_from_args(TwoInts, {"a": 1, "b": 2}) == TwoInts(a=1, b=2)
    assert message_from_args(TwoInts, [1, 2]) == TwoInts(a=1, b=2)

    class Defaults(RosMessage):
        text: String = "hi"

    assert message_from_args(Defaults, None).text == "hi"


def test_bad_arguments_name_each_wrong_field():
    with pytest.raises(BadArguments) as refused:
        message_from_args(TwoInts, {"a": "one"}, what="goal")
    assert "a: Input should be a valid integer" in str(refused.value)
    assert "b: Field required" in str(refused.value)
