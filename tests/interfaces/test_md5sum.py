"""genmsg's md5sums, against the values ROS 1's generated messages carry (genpy's `_md5sum`)."""

import hashlib

import pytest

from interfaces.md5sum import md5_text, md5sum
from interfaces.packages import Interfaces


@pytest.fixture(scope="module")
def ros1() -> Interfaces:
    interfaces = Interfaces([])
    interfaces.use_ros1()
    return interfaces


@pytest.mark.parametrize(
    ("type_name", "expected"),
    [
        ("std_msgs/String", "992ce8a1687cec8c8bd883ec73ca41d1"),  # md5("string data")
        ("std_msgs/Header", "2176decaecbce78abc3b96ef049fabed"),  # time: a builtin, written as it is
        ("geometry_msgs/Twist", "9f195f881246fdfa2798d1d3eebca84a"),  # nested types by their md5sums
        ("geometry_msgs/PoseStamped", "d3812c3cbc69362b77dc0b19b345f8f5"),  # Header nested
        ("sensor_msgs/JointState", "3066dcd76a6cfaef579bd0f34173e9fd"),  # builtin arrays
        ("actionlib_msgs/GoalStatus", "d388f9b87b3c471f784434d671988d4a"),  # constants first
    ],
)
def test_messages_have_genmsgs_md5sums(ros1: Interfaces, type_name: str, expected: str) -> None:
    assert md5sum(ros1.message(type_name)) == expected


def test_a_services_md5sum_is_of_its_request_then_its_response(ros1: Interfaces) -> None:
    add_two_ints = ros1.get("example_interfaces", "srv", "AddTwoInts")
    assert md5sum(add_two_ints) == hashlib.md5(b"int64 a\nint64 bint64 sum").hexdigest()
    assert md5sum(add_two_ints) == "6a2e34150c00229791cc89ff309fff21"  # rospy_tutorials' AddTwoInts


@pytest.mark.parametrize(
    ("name", "expected"),  # Debian's ros-core (roscpp.srv's generated classes): rospy's logger services
    [("GetLoggers", "32e97e85527d4678a8f9279894bb64b0"), ("SetLoggerLevel", "51da076440d78ca1684d36c868df61ea")],
)
def test_roscpps_logger_services_have_ros_1s_md5sums(ros1: Interfaces, name: str, expected: str) -> None:
    assert md5sum(ros1.get("roscpp", "srv", name)) == expected


def test_the_text_drops_comments_and_keeps_constants_before_fields(tmp_path) -> None:
    package = tmp_path / "demo_msgs" / "msg"
    package.mkdir(parents=True)
    (package / "Odd.msg").write_text(
        "# a comment\nint32 x   # trailing\n\nstring NAME = a # not a comment\nuint8 LOW=1\nstd_msgs/String[] words\n"
    )
    odd = Interfaces([tmp_path]).message("demo_msgs/Odd")
    string_md5 = "992ce8a1687cec8c8bd883ec73ca41d1"
    assert md5_text(odd) == f"string NAME=a # not a comment\nuint8 LOW=1\nint32 x\n{string_md5} words"
