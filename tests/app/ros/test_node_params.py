"""app/ros/node_params.py: a node's parameters reached through the standard parameter services it
provides (rcl_interfaces' fields): listed once it serves list_parameters and get_parameters, values
to and from rcl_interfaces/ParameterValue (an integer sent as a double to a double parameter), a
refused set with the node's own reason, its descriptor in Parameter.describe()'s shape, and a
wrong answer a 502 naming the service, never a 500."""

from __future__ import annotations

import math

import pytest

from app.ros.node_params import (
    BOOL,
    DOUBLE,
    DOUBLE_ARRAY,
    INTEGER,
    INTEGER_ARRAY,
    NOT_SET,
    STRING,
    STRING_ARRAY,
    NodeParameters,
    from_json,
    to_json,
)
from app.ros.node_services import NodeServices
from app.ros.params import ParameterRefused
from app.ros.services import ServiceRegistry
from tests.app.ros.nodes import Lab, Node, event_loop

TYPES = {"list_parameters": "ListParameters", "get_parameters": "GetParameters",
         "set_parameters": "SetParameters", "describe_parameters": "DescribeParameters"}  # fmt: skip


class Talker:
    """rclpy's parameter services of a node /talker: `rate` (integer, 1..100) and `gain` (double)."""

    def __init__(self) -> None:
        self.values = {"rate": {"type": INTEGER, "integer_value": 10}, "gain": {"type": DOUBLE, "double_value": 0.5}}
        self.sets: list[dict] = []

    def list_parameters(self, args: dict) -> tuple[bool, dict]:
        return True, {"result": {"names": sorted(self.values), "prefixes": []}}

    def get_parameters(self, args: dict) -> tuple[bool, dict]:
        return True, {"values": [self.values.get(name, {"type": NOT_SET}) for name in args["names"]]}

    def set_parameters(self, args: dict) -> tuple[bool, dict]:
        [parameter] = args["parameters"]
        self.sets.append(parameter)
        value = parameter["value"]
        if parameter["name"] == "rate" and not 1 <= value.get("integer_value", 0) <= 100:
            return True, {"results": [{"successful": False, "reason": "rate is 1 to 100"}]}
        self.values[parameter["name"]] = value
        return True, {"results": [{"successful": True, "reason": ""}]}

    def describe_parameters(self, args: dict) -> tuple[bool, dict]:
        descriptors = {
            "rate": {
                "name": "rate",
                "type": INTEGER,
                "description": "Hz",
                "read_only": False,
                "integer_range": [{"from_value": 1, "to_value": 100, "step": 1}],
            },
            "gain": {"name": "gain", "type": DOUBLE, "description": "", "read_only": True},
        }
        return True, {"descriptors": [descriptors.get(n, {"name": n, "type": NOT_SET}) for n in args["names"]]}


@pytest.fixture
def talker():
    """The node /talker serving its four parameter services; the lab's NodeParameters over them."""
    with event_loop() as loop:
        services = NodeServices(ServiceRegistry(), Lab())
        node, talker = Node("/talker", loop, services), Talker()
        for service, type_name in TYPES.items():
            node.serves[f"/talker/{service}"] = getattr(talker, service)
            services.advertise(f"/talker/{service}", f"rcl_interfaces/srv/{type_name}", node)
        talker.node, talker.services = node, services
        talker.parameters = NodeParameters(services)
        yield talker


def test_values_to_and_from_rcl_interfaces_parameter_value():
    assert from_json(True) == {"type": BOOL, "bool_value": True}
    assert from_json(3) == {"type": INTEGER, "integer_value": 3}
    assert from_json(3, DOUBLE) == {"type": DOUBLE, "double_value": 3.0}  # JSON has one number type
    assert from_json(0.25) == {"type": DOUBLE, "double_value": 0.25}
    assert from_json("x") == {"type": STRING, "string_value": "x"}
    assert from_json([1, 2]) == {"type": INTEGER_ARRAY, "integer_array_value": [1, 2]}
    assert from_json([1, 2], DOUBLE_ARRAY) == {"type": DOUBLE_ARRAY, "double_array_value": [1.0, 2.0]}
    assert from_json(["a"]) == {"type": STRING_ARRAY, "string_array_value": ["a"]}
    assert from_json(None) == {"type": NOT_SET}  # ros2 param delete
    for value in (True, 3, 0.25, "x", [1, 2], ["a"]):
        assert to_json(from_json(value)) == value
    assert to_json({"type": NOT_SET}) is None and to_json("not a value") is None and to_json({"type": 99}) is None


@pytest.mark.parametrize(
    ("value", "reason"),
    [
        (math.nan, "finite number"),
        (math.inf, "finite number"),
        ([1, "a"], "a bool, integer, double, string or an array"),
        ([], "a bool, integer, double, string or an array"),
        ({"a": 1}, "a bool, integer, double, string or an array"),
        ([[1]], "a parameter array holds bools, integers, doubles or strings"),
    ],
)
def test_a_value_no_parameter_can_hold_is_refused_with_the_reason(value, reason):
    with pytest.raises(ParameterRefused, match=reason):
        from_json(value)


def test_a_node_is_listed_once_it_serves_list_and_get_parameters(talker):
    assert talker.parameters.nodes() == ["talker"]
    talker.services.unadvertise("/talker/get_parameters", talker.node)
    assert talker.parameters.nodes() == []


def test_a_nodes_parameters_are_listed_read_and_set_through_its_services(talker):
    parameters = talker.parameters
    assert parameters.names("talker") == ["gain", "rate"]
    assert parameters.get("talker", ["rate", "gain", "other"]) == [10, 0.5, None]
    parameters.set("talker", "gain", 2)  # an integer to a double parameter: sent as a double
    assert talker.sets[-1] == {"name": "gain", "value": {"type": DOUBLE, "double_value": 2.0}}
    assert parameters.get("talker", ["gain"]) == [2.0]
    with pytest.raises(ParameterRefused, match=r"^rate is 1 to 100$") as refused:  # the node's reason as it is
        parameters.set("talker", "rate", 500)
    assert refused.value.status == 422 and parameters.get("talker", ["rate"]) == [10]


def test_a_nodes_descriptor_in_describes_shape(talker):
    assert talker.parameters.describe("talker", "rate") == {
        "node": "talker",
        "name": "rate",
        "type": "integer",
        "description": "Hz",
        "read_only": False,
        "default": None,
        "min_value": 1,
        "max_value": 100,
    }
    assert talker.parameters.describe("talker", "gain")["read_only"] is True
    with pytest.raises(ParameterRefused, match="Parameter not set") as missing:
        talker.parameters.describe("talker", "other")
    assert missing.value.status == 404


def test_without_describe_parameters_a_set_goes_by_the_values_own_type(talker):
    talker.services.unadvertise("/talker/describe_parameters", talker.node)
    talker.parameters.set("talker", "gain", 2)
    assert talker.sets[-1]["value"] == {"type": INTEGER, "integer_value": 2}


def test_a_service_the_node_does_not_provide_is_a_404_naming_it(talker):
    with pytest.raises(ParameterRefused, match="node /listener does not provide /listener/list_parameters") as gone:
        talker.parameters.names("listener")
    assert gone.value.status == 404


@pytest.mark.parametrize(
    ("service", "answer", "call", "reason"),
    [
        ("list_parameters", {"result": {"names": [1]}}, lambda p: p.names("talker"), "no result.names"),
        ("get_parameters", {"values": []}, lambda p: p.get("talker", ["rate"]), "0 values for 1 names"),
        ("set_parameters", {"results": []}, lambda p: p.set("talker", "rate", 5), "set_parameters answered no result"),
        ("describe_parameters", {"descriptors": 3}, lambda p: p.describe("talker", "rate"), "no descriptor for rate"),
    ],
)
def test_a_wrong_answer_is_a_502_naming_the_service(talker, service, answer, call, reason):
    talker.node.serves[f"/talker/{service}"] = lambda args: (True, answer)
    with pytest.raises(ParameterRefused, match=reason) as wrong:
        call(talker.parameters)
    assert wrong.value.status == 502


def test_a_failed_call_keeps_the_services_status(talker):
    talker.node.serves["/talker/get_parameters"] = lambda args: (False, "the node is shutting down")
    with pytest.raises(ParameterRefused, match="node /talker: service /talker/get_parameters failed in its node"):
        talker.parameters.get("talker", ["rate"])
