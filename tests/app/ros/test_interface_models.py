"""app/ros/interface_models.py: a carried .srv text becomes strict request/response models (each
field in its ROS type's range, a bounded string's bound, finite floats, a required field named when
missing), its fields as a caller sees them, and a text that cannot be read is refused by name."""

import pytest
from pydantic import ValidationError

from app.ros.interface_models import MAX_TEXT, BadDefinition, fields, own_text, service_models
from interfaces.packages import SEPARATOR

TEXT = "int8 a\nfloat64 b\nstring<=5 name\nbool flag\n---\nint64 sum\n"


def test_a_carried_srv_becomes_strict_request_and_response_models():
    request, response = service_models("my_pkg/Add", TEXT)
    ok = request.model_validate({"a": 3.0, "b": 1.5, "name": "abc", "flag": True})
    assert (ok.a, ok.b, ok.name, ok.flag) == (3, 1.5, "abc", True)  # 3.0 is 3, as JSON Schema says
    assert response.model_validate({"sum": 2**40}).sum == 2**40
    for bad, field in (
        ({"a": 200, "b": 0.0, "name": "", "flag": False}, "a"),  # int8's range
        ({"a": 1, "b": float("inf"), "name": "", "flag": False}, "b"),
        ({"a": 1, "b": 0.0, "name": "toolong", "flag": False}, "name"),  # string<=5
        ({"b": 0.0, "name": "", "flag": False}, "a"),  # required: no default in the text
    ):
        with pytest.raises(ValidationError) as refused:
            request.model_validate(bad)
        assert [error["loc"][0] for error in refused.value.errors()] == [field]


def test_the_fields_as_a_caller_sees_them():
    request, _ = service_models("my_pkg/srv/Add", TEXT)
    assert [(f["name"], f["type"]) for f in fields(request)] == [
        ("a", "int8"),
        ("b", "float64"),
        ("name", "string"),  # its bound checked, as above
        ("flag", "bool"),
    ]


def test_a_text_that_cannot_be_read_is_refused_by_name():
    with pytest.raises(BadDefinition, match=f"longer than {MAX_TEXT} characters"):
        service_models("my_pkg/Add", "int8 a\n" * MAX_TEXT)
    with pytest.raises(BadDefinition):
        service_models("my_pkg/Add", "int8\n---\n")  # a field without its name


def test_own_text_leaves_the_nested_messages_out():
    assert own_text(f"\nint8 a\n---\n{SEPARATOR}MSG: my_pkg/Point\nfloat64 x\n") == "int8 a\n---"
