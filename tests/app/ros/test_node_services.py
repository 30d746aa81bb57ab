"""app/ros/node_services.py: a service a node provides is called through the lab's registry (the
request sent to the node with the caller's header, its answer checked against the response model),
a node's answer replaces the lab's own while it serves a declared name, an exercise is not provided
until a node advertises it, a node that leaves fails its calls in flight at once, and a node's
answer of a service with an effect applies it to the lab."""

from __future__ import annotations

import asyncio
import threading
from concurrent.futures import Future

import pytest

from app.ros.messages import Bool, Int64, RosMessage
from app.ros.node_services import (
    NodeServices,
    OpenMessage,
    SetBoolRequest,
    SetBoolResponse,
    models_of,
    normalise_type,
)
from app.ros.services import NodeFailure, NodeTimeout, NotProvided, Service, ServiceFailure, ServiceRegistry
from tests.app.ros.nodes import Lab, Node, event_loop

ADD_SRV = "int64 a\nint64 b\n---\nint64 sum"


class AddRequest(RosMessage):
    a: Int64
    b: Int64


class AddResponse(RosMessage):
    sum: Int64


class Flag(RosMessage):
    on: Bool


def lab_add(lab, request: AddRequest) -> AddResponse:
    return AddResponse(sum=-(request.a + request.b))  # the lab's own answer, told apart from a node's


BASE = [
    Service("/add_two_ints", "hri_lab/AddTwoInts", AddRequest, AddResponse, lab_add, "adds"),
    Service("/exercise", "hri_lab/AddTwoInts", AddRequest, AddResponse, lab_add, "an exercise"),
    Service("/start", "hri_lab/Flag", Flag, Flag, lambda lab, request: Flag(on=True), "starts"),
]


@pytest.fixture
def loop():
    with event_loop() as running:
        yield running


@pytest.fixture
def lab():
    return Lab()


@pytest.fixture
def services(lab):
    applied: list = []
    registry = NodeServices(
        ServiceRegistry(BASE),
        lab,
        exercises=("/exercise", "/not_declared"),
        effects={"/start": lambda lab, request: applied.append(request.on)},
        caller="/hri_lab",
    )
    registry.applied = applied
    return registry


def in_thread(call) -> Future:
    """`call()` on a thread of its own (an HTTP request's): the future of its outcome."""
    future: Future = Future()

    def run() -> None:
        try:
            future.set_result(call())
        except Exception as exc:  # noqa: BLE001 - the test reads it from the future
            future.set_exception(exc)

    threading.Thread(target=run, daemon=True).start()
    return future


def test_a_nodes_service_is_called_through_the_registry_with_the_callers_header(services, lab, loop):
    node = Node("/setter", loop, services)
    assert services.advertise("/set_flag", "std_srvs/srv/SetBool", node) is None
    assert services.registry.get("/set_flag").request is SetBoolRequest  # std_srvs/SetBool known by name
    assert services.node_of("/set_flag") == "/setter" and services.goes_to_node("/set_flag")
    answer = in_thread(lambda: services.registry.call(lab, "/set_flag", SetBoolRequest(data=True)))
    call = node.next("call_service")
    assert (call["service"], call["args"], call["connection_header"]) == (
        "/set_flag",
        {"data": True},
        {"callerid": "/hri_lab"},
    )
    assert services.answer(node, call["id"], True, {"success": True, "message": "set"})
    assert answer.result(30) == SetBoolResponse(success=True, message="set")
    assert lab.logged("/set_flag answered by node /setter")


def test_a_nodes_answer_that_is_no_response_fails_the_call_naming_the_field(services, loop):
    node = Node("/adder", loop, services)
    services.advertise("/sum", "my_pkg/Add", node, text=ADD_SRV)
    node.serves["/sum"] = lambda args: (True, {"sum": "many"})
    with pytest.raises(NodeFailure, match=r"not a my_pkg/Add response.*sum") as failed:
        services.call("/sum", OpenMessage.model_validate({"a": 1, "b": 2}))
    assert failed.value.status == 502
    node.serves["/sum"] = lambda args: (False, "no sums today")  # result false: the values are its reason
    with pytest.raises(ServiceFailure, match="failed in its node: no sums today"):
        services.call("/sum", OpenMessage.model_validate({"a": 1, "b": 2}))
    node.serves["/sum"] = lambda args: (False, {"sum": args["a"] + args["b"]})  # rosbridge_suite delivers these
    assert services.call("/sum", OpenMessage.model_validate({"a": 1, "b": 2})).sum == 3


def test_a_node_that_does_not_answer_in_time_fails_the_call_naming_service_and_node(lab, loop):
    services = NodeServices(ServiceRegistry(BASE), lab, timeout=0.0)  # no time at all
    node = Node("/sleepy", loop, services)
    services.advertise("/set_flag", "std_srvs/SetBool", node)
    with pytest.raises(NodeTimeout, match="service /set_flag: node /sleepy did not answer") as late:
        services.call("/set_flag", SetBoolRequest(data=False))
    assert late.value.status == 504
    node.next("call_service")  # the request went all the same


def test_a_name_is_one_nodes_until_it_withdraws(services, loop):
    first, second = Node("/first", loop, services), Node("/second", loop, services)
    services.advertise("/set_flag", "std_srvs/SetBool", first)
    with pytest.raises(ServiceFailure, match="already provided by node /first"):
        services.advertise("/set_flag", "std_srvs/SetBool", second)
    assert not services.unadvertise("/set_flag", second)  # not its to withdraw
    assert services.unadvertise("/set_flag", first)
    assert services.registry.get("/set_flag") is None and services.node_of("/set_flag") is None
    services.advertise("/set_flag", "std_srvs/SetBool", second)
    assert services.node_of("/set_flag") == "/second"


def test_a_nodes_answer_replaces_the_labs_own_while_it_serves_a_declared_name(services, lab, loop):
    assert services.answers_itself("/add_two_ints")
    assert services.registry.call(lab, "/add_two_ints", AddRequest(a=2, b=3)).sum == -5
    node = Node("/adder", loop, services)
    node.serves["/add_two_ints"] = lambda args: (True, {"sum": args["a"] + args["b"]})
    assert services.advertise("/add_two_ints", "example_interfaces/srv/AddTwoInts", node, text=ADD_SRV) is None
    assert not services.answers_itself("/add_two_ints")
    assert services.registry.call(lab, "/add_two_ints", AddRequest(a=2, b=3)).sum == 5
    assert services.registry.get("/add_two_ints").type == "example_interfaces/srv/AddTwoInts"  # its own, same fields
    services.drop(node)  # it disconnects: the lab's own again
    assert services.registry.call(lab, "/add_two_ints", AddRequest(a=2, b=3)).sum == -5
    assert services.registry.get("/add_two_ints").type == "hri_lab/AddTwoInts"


def test_a_declared_name_served_with_other_fields_is_checked_against_the_labs_with_a_warning(services, lab, loop):
    node = Node("/odd", loop, services)
    warning = services.advertise("/add_two_ints", "my_pkg/Odd", node, text="string a\n---\nstring sum")
    assert warning is not None and "declared by the lab as hri_lab/AddTwoInts" in warning
    assert lab.logged("declared by the lab as hri_lab/AddTwoInts")
    assert services.registry.get("/add_two_ints").type == "hri_lab/AddTwoInts"


def test_an_exercise_is_not_provided_until_a_node_advertises_it(services, lab, loop):
    assert not services.offered("/exercise") and services.goes_to_node("/exercise")
    assert services.offered("/add_two_ints")
    with pytest.raises(NotProvided, match="/exercise is not provided yet: a node must advertise it") as missing:
        services.registry.call(lab, "/exercise", AddRequest(a=1, b=1))
    assert missing.value.status == 404
    assert "Left to the students" in services.registry.get("/exercise").description
    node = Node("/student", loop, services)
    node.serves["/exercise"] = lambda args: (True, {"sum": args["a"] + args["b"]})
    services.advertise("/exercise", "hri_lab/AddTwoInts", node)
    assert services.offered("/exercise")
    assert services.registry.call(lab, "/exercise", AddRequest(a=1, b=1)).sum == 2
    assert "/not_declared" not in services.slots  # only declared names are left to the students


def test_a_node_that_leaves_fails_its_calls_in_flight_at_once(services, lab, loop):
    node = Node("/leaving", loop, services)
    services.advertise("/set_flag", "std_srvs/SetBool", node)
    answer = in_thread(lambda: services.call("/set_flag", SetBoolRequest(data=True)))
    node.next("call_service")
    services.drop(node)
    with pytest.raises(NodeFailure, match="node /leaving withdrew service /set_flag before answering"):
        answer.result(30)
    with pytest.raises(NotProvided, match="/set_flag is not advertised"):
        services.call("/set_flag", SetBoolRequest(data=True))


def test_only_the_called_node_answers_its_call(services, loop):
    node, other = Node("/called", loop, services), Node("/other", loop, services)
    services.advertise("/set_flag", "std_srvs/SetBool", node)
    answer = in_thread(lambda: services.call("/set_flag", SetBoolRequest(data=True)))
    call = node.next("call_service")
    assert not services.answer(other, call["id"], True, {"success": False, "message": "not mine"})
    assert not services.answer(node, 7, True, {})  # the lab's calls have string ids
    assert services.answer(node, call["id"], True, {"success": True, "message": ""})
    assert answer.result(30).success is True


def test_a_nodes_answer_of_a_service_with_an_effect_applies_it_to_the_lab(services, lab, loop):
    node = Node("/starter", loop, services)
    node.serves["/start"] = lambda args: (True, {"on": args["on"]})
    services.advertise("/start", "hri_lab/Flag", node)
    services.call("/start", Flag(on=True))
    assert services.applied == [True]
    node.serves["/start"] = lambda args: (True, {"on": "yes"})  # no response: no effect
    with pytest.raises(NodeFailure):
        services.call("/start", Flag(on=False))
    assert services.applied == [True]


def test_a_node_calls_another_nodes_service_from_the_event_loop_with_its_header(services, lab, loop):
    node = Node("/adder", loop, services)
    services.advertise("/sum", "my_pkg/Add", node, text=ADD_SRV)
    request = services.registry.get("/sum").request.model_validate({"a": 4, "b": 5})
    answer = asyncio.run_coroutine_threadsafe(services.call_async("/sum", request, {"callerid": "/caller"}), loop)
    call = node.next("call_service")
    assert call["connection_header"] == {"callerid": "/caller"}
    services.answer(node, call["id"], True, {"sum": 9})
    assert answer.result(30).sum == 9
    assert lab.logged("/sum answered by node /adder")


def test_an_unknown_type_passes_through_and_an_unreadable_text_is_refused_by_name(services, loop):
    node = Node("/any", loop, services)
    services.advertise("/any", "my_pkg/srv/Unknown", node)
    assert services.registry.get("/any").request is OpenMessage
    assert "unknown to the lab" in services.registry.get("/any").description
    with pytest.raises(ServiceFailure, match="the definition of my_pkg/Bad cannot be read"):
        models_of("my_pkg/Bad", "int64\n---\n")
    with pytest.raises(ServiceFailure, match="cannot be read"):
        services.advertise("/bad", "my_pkg/Bad", node, text="int64\n---\n")
    assert services.registry.get("/bad") is None


def test_a_ros2_type_name_is_read_as_its_ros1_spelling():
    assert normalise_type("std_srvs/srv/SetBool") == "std_srvs/SetBool"
    assert normalise_type("/my_pkg/action/Fib") == "my_pkg/Fib"
    assert normalise_type("std_srvs/SetBool") == "std_srvs/SetBool"
