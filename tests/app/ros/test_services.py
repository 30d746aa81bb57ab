"""app/ros/services.py: the registry (declared once, found by any spelling of the name, replaced and
removed while nodes come and go) and a service's .srv text and introspection."""

import pytest

from app.ros.messages import Int64, RosMessage, String
from app.ros.services import NodeFailure, NodeTimeout, NotProvided, Service, ServiceFailure, ServiceRegistry


class TwoInts(RosMessage):
    a: Int64
    b: Int64


class Sum(RosMessage):
    sum: Int64


class Text(RosMessage):
    text: String


def add(lab, request: TwoInts) -> Sum:
    return Sum(sum=request.a + request.b + lab)


ADD = Service("/add_two_ints", "hri_lab/AddTwoInts", TwoInts, Sum, add, "a + b")


def test_a_call_runs_the_handler_with_the_lab_and_the_request():
    registry = ServiceRegistry([ADD])
    assert registry.call(100, "add_two_ints", TwoInts(a=1, b=2)) == Sum(sum=103)  # `lab` reaches the handler
    with pytest.raises(KeyError, match="/nothing"):
        registry.call(0, "nothing", TwoInts(a=1, b=2))


def test_a_name_is_declared_once_and_found_by_any_spelling():
    registry = ServiceRegistry([ADD])
    with pytest.raises(ValueError, match="declared twice"):
        registry.add(ADD)
    assert registry.get("add_two_ints/") is ADD
    assert registry.get("/other") is None
    assert [s.name for s in registry] == ["/add_two_ints"]


def test_put_replaces_in_place_and_remove_takes_it_away():
    echo = Service("/echo", "hri_lab/Echo", Text, Text, lambda lab, r: r)
    registry = ServiceRegistry([echo, ADD])
    node_text = Service("/echo", "hri_lab/Echo", Text, Text, lambda lab, r: r, text="string text\n---\nstring text")
    registry.put(node_text)
    assert [s.name for s in registry] == ["/echo", "/add_two_ints"]
    assert registry.get("/echo").srv == node_text.text
    assert registry.remove("echo") is node_text
    assert registry.remove("echo") is None
    assert [s.name for s in registry] == ["/add_two_ints"]


def test_the_srv_text_and_the_introspection_come_from_the_models():
    assert ADD.srv == "int64 a\nint64 b\n---\nint64 sum"
    info = ADD.info()
    assert (info["name"], info["type"], info["description"]) == ("/add_two_ints", "hri_lab/AddTwoInts", "a + b")
    assert [f["name"] for f in info["request_fields"]] == ["a", "b"]
    assert info["response_schema"]["properties"]["sum"]["type"] == "integer"


def test_each_failure_carries_its_http_status():
    assert (ServiceFailure.status, NotProvided.status, NodeTimeout.status, NodeFailure.status) == (400, 404, 504, 502)
    assert all(issubclass(c, ServiceFailure) for c in (NotProvided, NodeTimeout, NodeFailure))
