"""rclpy.node.Node (rosclient/site/rclpy/node.py and the modules it makes entities with) in this
process, over the recording connection: pre- and post-set parameter callbacks as rclpy calls them,
the logger service's levels, and a raw subscription's bytes."""

import json
import re

import pytest


def test_pre_set_callbacks_change_what_is_set_and_post_set_ones_hear_of_it(rclpy):
    from rclpy.parameter import Parameter

    node = rclpy.create_node("params", start_parameter_services=False)
    node.declare_parameter("param1", 0.0)
    node.declare_parameter("param2", 0.0)
    heard: list[list[str]] = []
    node.add_pre_set_parameters_callback(lambda ps: [*ps, Parameter("param2", Parameter.Type.DOUBLE, 4.0)])
    node.add_post_set_parameters_callback(lambda ps: heard.append([p.name for p in ps]))
    results = node.set_parameters([Parameter("param1", Parameter.Type.DOUBLE, 10.0)])
    assert [r.successful for r in results] == [True]
    assert node.get_parameter("param2").value == 4.0 and node.get_parameter("param1").value == 10.0
    assert heard == [["param1", "param2"]]
    node.add_pre_set_parameters_callback(lambda ps: [])
    node.remove_pre_set_parameters_callback(node._pre_set_callbacks[0])
    refused = node.set_parameters_atomically([Parameter("param1", Parameter.Type.DOUBLE, 1.0)])
    assert not refused.successful and "cannot be empty" in refused.reason
    assert node.get_parameter("param1").value == 10.0 and heard == [["param1", "param2"]]


def test_the_logger_service_reads_and_sets_a_nodes_level(rclpy):
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.logging import LoggingSeverity, get_logger

    node = rclpy.create_node("LoggerServiceNode", start_parameter_services=False, enable_logger_service=True)
    connection = rclpy.connection
    levels = {"names": ["LoggerServiceNode"]}
    connection.call("/LoggerServiceNode/get_logger_levels", "get:1", levels)
    connection.call(
        "/LoggerServiceNode/set_logger_levels", "set:1", {"levels": [{"name": "LoggerServiceNode", "level": 40}]}
    )
    connection.call("/LoggerServiceNode/get_logger_levels", "get:2", levels)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    for _ in range(3):  # one request of each service per round, in the order they came
        executor.spin_once(timeout_sec=5)
    answers = {m["id"]: m["values"] for m in connection.sent if m["op"] == "service_response"}
    assert answers["get:1"] == {"levels": [{"name": "LoggerServiceNode", "level": 0}]}  # unset, as rcutils says
    assert answers["set:1"] == {"results": [{"successful": True, "reason": ""}]}
    assert answers["get:2"] == {"levels": [{"name": "LoggerServiceNode", "level": 40}]}
    assert get_logger("LoggerServiceNode").get_effective_level() == LoggingSeverity.ERROR


def test_a_raw_subscription_gets_the_message_as_it_travelled(rclpy):
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    node = rclpy.create_node("raw", start_parameter_services=False)
    got: list[object] = []
    node.create_subscription(String, "chatter", got.append, 10, raw=True)
    rclpy.connection.publish("/chatter", {"data": "hi"})
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.spin_once(timeout_sec=5)
    assert got == [json.dumps({"data": "hi"}).encode()]


def test_numeric_sequences_are_typed_arrays_as_rclpy_gives_them(rclpy):
    """rclpy's generated messages: a numeric sequence is an array.array of its type (a list given
    is converted when set), a fixed-size numeric array a numpy array, a byte array bytes; rosbridge's
    JSON both ways."""
    import array

    import numpy
    from example_interfaces.action import Fibonacci
    from geometry_msgs.msg import PoseWithCovariance
    from sensor_msgs.msg import Image, JointState

    result = Fibonacci.Result()
    assert repr(result.sequence) == "array('i')"
    result.sequence = [0, 1, 1]
    result.sequence.append(2)
    assert repr(result.sequence) == "array('i', [0, 1, 1, 2])"  # what a goal's result prints
    assert result.to_json() == {"sequence": [0, 1, 1, 2]}
    assert Fibonacci.Result.from_json({"sequence": [0, 1]}).sequence == array.array("i", [0, 1])
    joints = JointState(position=[1.0, 2.0])
    assert joints.position == array.array("d", [1.0, 2.0]) and joints.velocity == array.array("d")
    assert JointState.from_json(joints.to_json()) == joints
    pose = PoseWithCovariance()
    assert isinstance(pose.covariance, numpy.ndarray) and pose.covariance.dtype == numpy.float64
    assert pose == PoseWithCovariance() and pose.to_json()["covariance"] == [0.0] * 36
    assert Image().data == b""  # uint8[] stays bytes (the lab's images)
    result.sequence = ["not a number"]  # kept as given: publishing it names the field
    with pytest.raises(
        TypeError, match=re.escape("'example_interfaces/FibonacciResult.sequence' field must be of type 'int'")
    ):
        result.to_json()


def test_parameter_events_are_published_and_a_handler_calls_its_callbacks_newest_first(rclpy):
    """ROS 2's "Monitoring for parameter changes" tutorial: a node's declared and set parameters go out
    on /parameter_events (rclpy's ParameterEvent); a ParameterEventHandler's callbacks of that node's
    parameter get its rcl_interfaces/Parameter, its event callbacks every event."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.parameter import Parameter, parameter_value_to_python
    from rclpy.parameter_event_handler import ParameterEventHandler

    node = rclpy.create_node("node_with_parameters", start_parameter_services=False)
    connection = rclpy.connection
    handler = ParameterEventHandler(node)
    heard: list[tuple[str, str, object]] = []
    first = handler.add_parameter_callback(
        "an_int_param",
        "node_with_parameters",
        lambda p: heard.append(("first", p.name, parameter_value_to_python(p.value))),
    )
    handler.add_parameter_callback(
        "an_int_param",
        "/node_with_parameters",
        lambda p: heard.append(("second", p.name, parameter_value_to_python(p.value))),
    )
    events: list[object] = []
    handler.add_parameter_event_callback(events.append)
    node.declare_parameter("an_int_param", 0)
    node.set_parameters([Parameter("an_int_param", Parameter.Type.INTEGER, 43)])
    node.set_parameters([Parameter("an_int_param", Parameter.Type.NOT_SET)])
    advertised = [m for m in connection.sent if m["op"] == "advertise" and m["topic"] == "/parameter_events"]
    assert advertised and advertised[0]["type"] == "rcl_interfaces/msg/ParameterEvent"
    sent = [m["msg"] for m in connection.sent if m["op"] == "publish" and m["topic"] == "/parameter_events"]
    assert [
        (e["node"], len(e["new_parameters"]), len(e["changed_parameters"]), len(e["deleted_parameters"])) for e in sent
    ] == [("/node_with_parameters", 1, 0, 0), ("/node_with_parameters", 0, 1, 0), ("/node_with_parameters", 0, 0, 1)]
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    for event in sent:  # as the lab relays them back to the program's subscription
        connection.publish("/parameter_events", event)
        executor.spin_once(timeout_sec=5)
    assert heard == [
        ("second", "an_int_param", 0),
        ("first", "an_int_param", 0),  # newest first
        ("second", "an_int_param", 43),
        ("first", "an_int_param", 43),
    ]  # a deletion: none
    assert len(events) == 3 and events[2].deleted_parameters[0].name == "an_int_param"
    handler.remove_parameter_callback(first)
    with pytest.raises(RuntimeError, match="Callback doesn't exist"):
        handler.remove_parameter_callback(first)
    handler.destroy()
