"""A relayed message made whole (app/rosbridge/internal/message_conversion.py), as rosbridge_suite's
populate_instance makes a ROS message of what a client publishes: defaults where fields are left
out (nested messages, arrays), a field the type does not have or a wrong value refused by name,
a type the lab does not know relayed as it came."""

import pytest

from app.rosbridge.internal.message_conversion import FieldError, converter, populate
from interfaces.packages import Interfaces, full_text

ZERO_TIME = {"sec": 0, "nanosec": 0, "secs": 0, "nsecs": 0}  # left out: in ROS 2's spelling and ROS 1's


def refused(type_name: str, message: dict, definition: str = "") -> str:
    with pytest.raises(FieldError) as caught:
        populate(type_name, definition, message)
    return caught.value.describe(type_name)


def test_a_ros1_cancel_of_its_id_alone_gets_its_stamp():
    assert populate("actionlib_msgs/GoalID", "", {"id": "goal_1"}) == {"stamp": ZERO_TIME, "id": "goal_1"}
    assert populate("actionlib_msgs/GoalID", "", {}) == {"stamp": ZERO_TIME, "id": ""}


def test_nested_messages_are_filled_at_every_level_and_given_values_kept():
    whole = populate("actionlib/TestActionResult", "", {"status": {"goal_id": {"id": "g"}, "status": 2}})
    assert whole == {
        "header": {"stamp": ZERO_TIME, "frame_id": ""},
        "status": {"goal_id": {"stamp": ZERO_TIME, "id": "g"}, "status": 2, "text": ""},
        "result": {"result": 0},  # actionlib/TestAction's default result (roslibpy's preempted goal)
    }
    given = populate("actionlib_msgs/GoalID", "", {"id": "g", "stamp": {"secs": 7}})
    assert given == {"stamp": {"secs": 7, "nsecs": 0}, "id": "g"}  # a stamp's spelling kept, its other part 0
    assert populate("builtin_interfaces/Time", "", {"sec": 3}) == {"sec": 3, "nanosec": 0}


def test_arrays_are_filled_checked_item_by_item_and_numbers_made_floats():
    state = populate("sensor_msgs/JointState", "", {"name": ["a", "b"], "position": [1, 2.5]})
    assert state["position"] == [1.0, 2.5]
    assert all(type(p) is float for p in state["position"])
    assert state["velocity"] == [] and state["effort"] == []
    info = populate("sensor_msgs/CameraInfo", "", {"width": 640})
    assert info["k"] == [0.0] * 9  # a fixed-size array: its N zeros
    assert refused("sensor_msgs/CameraInfo", {"k": [0.0] * 8}) == (
        "sensor_msgs/CameraInfo message: field 'k' requires 9 items (float64[9]), got 8"
    )
    assert "field 'position.1' must be of type float64" in refused("sensor_msgs/JointState", {"position": [1.0, "x"]})
    assert "field 'position' must be an array (float64[])" in refused("sensor_msgs/JointState", {"position": 1.0})
    assert "field 'name.0' must be of type string, got null" in refused("sensor_msgs/JointState", {"name": [None]})
    image = populate("sensor_msgs/Image", "", {"data": "AAEC", "width": 1})
    assert image["data"] == "AAEC"  # a uint8[] as rosbridge's base64 text passes as it is
    pixels = list(range(256)) * 100
    assert populate("sensor_msgs/Image", "", {"data": pixels})["data"] == pixels  # as a list of byte values
    assert "field 'data.25600' must be of type uint8 (an integer in [0, 255]), got an integer 256" in (
        refused("sensor_msgs/Image", {"data": [*pixels, 256]})
    )
    assert "field 'data.1' must be of type uint8" in refused("sensor_msgs/Image", {"data": [1, 2.0]})


def test_a_field_the_type_does_not_have_is_refused_with_its_name():
    assert refused("actionlib_msgs/GoalID", {"id": "g", "stamp": {"secs": 1, "nsec": 2}}) == (
        "actionlib_msgs/GoalID message: field 'stamp.nsec' does not exist: "
        "a time {sec, nanosec} or {secs, nsecs} has no field 'nsec'"
    )
    assert refused("actionlib/TestActionGoal", {"goal": {"gaol": 3}}) == (
        "actionlib/TestActionGoal message: field 'goal.gaol' does not exist: actionlib/TestGoal has no field 'gaol'"
    )


def test_a_wrong_type_is_refused_with_the_field_and_what_it_must_be():
    assert refused("actionlib_msgs/GoalID", {"id": 3}) == (
        "actionlib_msgs/GoalID message: field 'id' must be of type string, got an integer 3"
    )
    assert "field 'data' must be of type bool" in refused("std_msgs/Bool", {"data": 1})
    assert "field 'goal.goal' must be of type int32 (an integer in [-2147483648, 2147483647]), got a number 1.5" in (
        refused("actionlib/TestActionGoal", {"goal": {"goal": 1.5}})
    )
    assert "must be of type int32" in refused("actionlib/TestActionGoal", {"goal": {"goal": 2**31}})
    assert "must be of type int32" in refused("actionlib/TestActionGoal", {"goal": {"goal": True}})
    assert "field 'header' must be a std_msgs/Header (an object), got a string" in (
        refused("actionlib/TestActionGoal", {"header": "now"})
    )
    assert "gives two different times" in refused(
        "builtin_interfaces/Time", {"sec": 1, "nanosec": 0, "secs": 2, "nsecs": 0}
    )


def test_a_ros1_header_keeps_its_seq_and_a_wrong_one_is_refused():
    whole = populate("std_msgs/Header", "", {"seq": 4, "stamp": {"secs": 1, "nsecs": 5}, "frame_id": "map"})
    assert whole == {"stamp": {"secs": 1, "nsecs": 5}, "frame_id": "map", "seq": 4}
    assert "field 'header.seq' must be of type uint32" in refused("actionlib/TestActionGoal", {"header": {"seq": -1}})


def test_ros1s_capitals_of_camera_info_are_kept_as_ros1s():
    info = populate("sensor_msgs/CameraInfo", "", {"K": [1.0, 0, 2, 0, 1, 2, 0, 0, 1], "D": []})
    assert info["K"] == [1.0, 0.0, 2.0, 0.0, 1.0, 2.0, 0.0, 0.0, 1.0]  # checked and kept under ROS 1's name
    assert "k" not in info and "d" not in info and info["r"] == [0.0] * 9  # the others filled as ROS 2 has them
    assert "field 'K' requires 9 items" in refused("sensor_msgs/CameraInfo", {"K": [1.0]})


def test_a_type_the_lab_does_not_know_is_relayed_as_it_came():
    message = {"anything": [1, "two"], "goal_id": 3}
    assert populate("actionlib_tutorials/FibonacciActionGoal", "", message) is message
    assert converter("not a type", "") is None


def test_the_definition_a_program_carried_gives_its_type_and_defaults():
    definition = "int32 count 5\nstring label\ngeometry_msgs/Point[] points\n"  # a ROS 2 default value
    assert populate("my_pkg/Marks", definition, {"label": "x"}) == {"count": 5, "label": "x", "points": []}
    assert "field 'points.0.z' must be of type float64" in (
        refused("my_pkg/Marks", {"points": [{"z": "up"}]}, definition)
    )
    ros1 = Interfaces([]).message("actionlib_msgs/GoalStatus")  # a nested definition carried as full_text
    assert populate("actionlib_msgs/GoalStatus", full_text(ros1), {"status": 1})["goal_id"]["id"] == ""


def test_a_types_converter_is_made_once():
    assert converter("actionlib_msgs/GoalID", "") is converter("actionlib_msgs/GoalID", "")
