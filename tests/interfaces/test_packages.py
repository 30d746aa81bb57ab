"""Interfaces from text (interfaces/): the classes genpy and rosidl make of .msg, .srv and
.action files, the errors of bad definitions, and a definition carried as text."""

import base64
import binascii

import pytest

from interfaces.packages import Interfaces, full_text
from interfaces.parser import DefinitionError
from tests.ros_running import PROGRAMS


@pytest.fixture
def interfaces(tmp_path):
    return Interfaces([tmp_path, PROGRAMS])


def test_a_workspace_service_has_rclpy_and_rospy_classes_with_ros_defaults(interfaces):
    multiply = interfaces.get("cpp_package", "srv", "MultiplyThree")
    request = multiply.Request()
    assert (request.a, request.b, request.c) == (0, 0, 0)
    assert multiply._request_class is multiply.Request
    assert multiply._type == "cpp_package/MultiplyThree"
    assert multiply.Request(1, 2, 3).to_json() == {"a": 1, "b": 2, "c": 3}  # rospy: positional
    assert multiply.Request(b=5).to_json() == {"a": 0, "b": 5, "c": 0}  # keyword, the rest default
    assert multiply.Response.from_json({"product": 6}).product == 6
    divide = interfaces.get("cpp_package", "srv", "DivideInts")
    assert divide.Response().result == 0.0
    assert divide.Response().message == ""


def test_a_wrong_field_or_type_is_an_error_naming_it(interfaces):
    add = interfaces.get("example_interfaces", "srv", "AddTwoInts")
    with pytest.raises(TypeError, match=r"has no field 'c'.*a, b"):
        add.Request(a=1, c=2)
    with pytest.raises(AttributeError, match="'c'"):
        add.Request().c = 3
    bad = add.Request(a="1")
    with pytest.raises(TypeError, match=r"'example_interfaces/AddTwoIntsRequest.a' field must be of type 'int'"):
        bad.to_json()
    with pytest.raises(ValueError, match=r"int64"):
        add.Request(a=2**63).to_json()


def test_nested_messages_arrays_constants_and_header_stamps(interfaces):
    wrench = interfaces.message("geometry_msgs/WrenchStamped")
    msg = wrench.from_json(
        {
            "header": {"stamp": {"sec": 3, "nanosec": 500000000}, "frame_id": "panda_K"},
            "wrench": {"force": {"x": 1, "y": 2.5, "z": -3}, "torque": {"x": 0, "y": 0, "z": 0}},
        }
    )
    assert msg.wrench.force.x == 1.0
    assert isinstance(msg.wrench.force.x, float)
    assert msg.header.stamp.to_sec() == 3.5
    assert msg.header.stamp.secs == 3
    assert interfaces.message("geometry_msgs/Quaternion")().w == 1.0  # a default in the definition
    joint = interfaces.message("sensor_msgs/msg/JointState")(position=[0.1, 0.2], name=["a", "b"])
    assert joint.to_json()["position"] == [0.1, 0.2]
    assert joint.velocity == []
    log = interfaces.message("rosgraph_msgs/Log")
    assert (log.INFO, log.ERROR) == (2, 8)
    status = interfaces.message("actionlib_msgs/GoalStatus")
    assert status.SUCCEEDED == 3
    assert status().goal_id.id == ""
    image = interfaces.message("sensor_msgs/Image")(data=b"\x01\x02")
    assert image.to_json()["data"] == "AQI="  # uint8[] as base64, as rosbridge sends it
    assert interfaces.message("sensor_msgs/Image").from_json({"data": "AQI="}).data == b"\x01\x02"


def test_base64_byte_arrays_decode_as_the_standard_library_does(interfaces):
    """The SIMD decoder (pybase64) gives base64.b64decode's bytes, including for text with
    characters outside the alphabet (skipped), and refuses bad padding as it does."""
    image = interfaces.message("sensor_msgs/Image")
    data = bytes(range(256)) * 3
    text = base64.b64encode(data).decode("ascii")
    assert image.from_json({"data": text}).data == data
    wrapped = "\n".join(text[i : i + 76] for i in range(0, len(text), 76))  # MIME's lines
    assert image.from_json({"data": wrapped}).data == base64.b64decode(wrapped) == data
    with pytest.raises(binascii.Error):
        image.from_json({"data": "AQI"})


def test_an_array_field_of_json_that_is_no_array_is_a_type_error_naming_it(interfaces):
    joint = interfaces.message("sensor_msgs/JointState")
    with pytest.raises(TypeError, match=r"'position' field must be a JSON array.*got str"):
        joint.from_json({"position": "0.1"})  # once iterated character by character
    with pytest.raises(TypeError, match=r"'position' field must be a JSON array.*got dict"):
        joint.from_json({"position": {"a": 1}})
    image = interfaces.message("sensor_msgs/Image")
    assert image.from_json({"data": [1, 2]}).data == b"\x01\x02"  # uint8[] as a list of numbers
    with pytest.raises(TypeError, match="'data' field must be a list of byte values"):
        image.from_json({"data": [1, "2"]})
    assert joint(position=(0.5,)).to_json()["position"] == [0.5]  # a Python program's tuple


def test_an_action_has_goal_result_feedback(interfaces):
    counting = interfaces.get("cpp_package", "action", "Counting")
    assert counting.Goal(count=3).count == 3
    assert counting.Feedback().current == 0
    assert counting.Result().reached == 0


def test_the_lab_interfaces_are_its_own_declarations(interfaces):
    from app.lab.services import SERVICES

    divide = interfaces.get("hri_lab", "srv", "DivideInts")
    assert divide._definition.strip() == next(s.srv for s in SERVICES if s.type == "hri_lab/DivideInts").strip()
    assert set(divide.Response.get_fields_and_field_types()) == {"result", "message"}
    echo = interfaces.get("hri_lab", "srv", "Echo")
    assert echo.Request(in_="x").to_json() == {"in": "x"}  # a keyword field gets genpy's trailing _
    assert "count" in interfaces.get("hri_lab", "action", "Count").Goal().to_json()


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("int64 a\nint64\n", "line 2: expected 'TYPE NAME'"),
        ("int64 a\nfoo bar\n", "line 2: unknown type 'foo'|cannot be read"),
        ("int64 a\nint64 a\n", "line 2: field 'a' is defined twice"),
        ("int32 X=abc\n", "line 1: expected a int32 value"),
        # the attack suite (docs/operations.md): caps, with the file and line
        ("int64 a\nfloat64[30000000] v\n", "line 2: a fixed-size array of at most 65536 items, got 30000000"),
        ("float64[<=99999999999999999999] v\n", "line 1: a size or bound of at most 9 digits"),
        ("string<=1" + "0" * 5000 + " s\n", "line 1: a size or bound of at most 9 digits"),
        ("int64 X=9223372036854775808\n", r"line 1: 9223372036854775808 is out of int64's range"),
        ("uint8 X=-1\n", r"line 1: -1 is out of uint8's range"),
        ("int32 a 4294967296\n", r"line 1: 4294967296 is out of int32's range"),
        (
            "int64 a\nBad again\n",
            r"line 2: field 'again' has type my_pkg/Bad.*contains itself \(my_pkg/Bad -> my_pkg/Bad\)",
        ),
        ("# " + "x" * 70_000 + "\nint64 a\n", "70011 characters, at most 65536"),
    ],
)
def test_a_malformed_definition_is_an_import_error_naming_file_and_line(tmp_path, text, expected):
    (tmp_path / "my_pkg" / "msg").mkdir(parents=True)
    (tmp_path / "my_pkg" / "msg" / "Bad.msg").write_text(text)
    with pytest.raises(ImportError, match=expected) as error:
        Interfaces([tmp_path]).get("my_pkg", "msg", "Bad")
    assert "Bad.msg" in str(error.value)


def test_a_missing_definition_names_where_it_was_looked_for(tmp_path):
    (tmp_path / "my_pkg" / "srv").mkdir(parents=True)
    with pytest.raises(DefinitionError, match=r"cannot import name 'Nope' from 'my_pkg.srv'.*my_pkg/srv/Nope.srv"):
        Interfaces([tmp_path]).get("my_pkg", "srv", "Nope")
    (tmp_path / "my_pkg" / "srv" / "Half.srv").write_text("int64 a\n")
    with pytest.raises(DefinitionError, match="expected 2 sections separated by '---'"):
        Interfaces([tmp_path]).get("my_pkg", "srv", "Half")


def test_a_carried_srv_text_makes_the_labs_request_and_response_models(interfaces):
    """What a program's advertise_service carries (full_text: the .srv, then each nested message's
    text) is all the lab needs: its models check a request as the program's type says, naming the
    field, with the text's defaults, ranges, array lengths and nested messages."""
    from pydantic import ValidationError

    from app.ros.interface_models import BadDefinition, fields, own_text, service_models
    from interfaces.packages import full_text

    text = full_text(interfaces.get("cpp_package", "srv", "ScalePoint"))
    assert "MSG: geometry_msgs/Point" in text
    assert "MSG: cpp_package/Note" in text
    assert own_text(text) == (PROGRAMS / "cpp_package/srv/ScalePoint.srv").read_text().strip()
    request, response = service_models("cpp_package/srv/ScalePoint", text)
    ok = request.model_validate({"point": {"x": 1, "y": 2.5}, "factor": 2})
    assert ok.model_dump(by_alias=True) == {"point": {"x": 1.0, "y": 2.5, "z": 0.0}, "factor": 2.0, "digits": 2}
    for body, field in [
        ({"point": {"x": 1, "y": 2}}, ("factor",)),  # missing (a nested message's field takes its default)
        ({"point": {"x": "one"}, "factor": 2}, ("point", "x")),  # a nested field of the wrong type
        ({"point": {"x": 1, "y": 2, "z": 3}, "factor": "2"}, ("factor",)),  # a string is not a number
        ({"point": {"x": 1, "y": 2, "z": 3}, "factor": 2, "digits": 256}, ("digits",)),  # uint8
        ({"point": {"x": 1, "y": 2, "z": 3}, "factor": 2, "unit": "m"}, ("unit",)),  # not in the .srv
    ]:
        with pytest.raises(ValidationError) as refused:
            request.model_validate(body)
        assert [e["loc"] for e in refused.value.errors()] == [field]
    assert fields(response) == [
        {"name": "scaled", "type": "geometry_msgs/Point"},
        {"name": "note", "type": "cpp_package/Note"},
    ]
    # keywords and arrays: `in` keeps its wire name; a fixed array its length
    echo, _ = service_models("pkg/Echo", "string in\nfloat64[3] xyz\nuint8[] data\n---\n")
    assert echo.model_validate({"in": "a", "xyz": [1, 2, 3], "data": "AAE="}).model_dump(by_alias=True)["in"] == "a"
    with pytest.raises(ValidationError, match="xyz"):
        echo.model_validate({"in": "a", "xyz": [1, 2], "data": []})
    with pytest.raises(ValidationError, match="in\n"):
        echo.model_validate({"xyz": [1, 2, 3], "data": []})
    with pytest.raises(BadDefinition, match="line 2: expected 'TYPE NAME'"):
        service_models("pkg/Bad", "int64 a\nint64\n---\n")
    with pytest.raises(BadDefinition, match="expected 2 sections"):
        service_models("pkg/Bad", "int64 a\n")


def test_an_actions_topic_messages_are_genmsgs(interfaces):
    """actionlib's topics carry XActionGoal, XActionResult, XActionFeedback (genmsg's genaction):
    a Header, the goal's id or status, then the goal, result or feedback."""
    goal = interfaces.message("cpp_package/CountingActionGoal")
    assert [f.name for f in goal._fields] == ["header", "goal_id", "goal"]
    made = goal(goal_id={"id": "g1"}, goal=interfaces.message("cpp_package/CountingGoal")(count=3))
    assert made.to_json()["goal"] == {"count": 3}
    assert goal.from_json({"goal_id": {"id": "g1", "stamp": {"secs": 1, "nsecs": 5}}}).goal_id.stamp.nsecs == 5
    result = interfaces.message("cpp_package/CountingActionResult")
    assert [f.name for f in result._fields] == ["header", "status", "result"]
    assert result().status.SUCCEEDED == 3
    action = interfaces.message("cpp_package/CountingAction")
    assert [f.msg_class for f in action._fields] == [
        goal,
        result,
        interfaces.message("cpp_package/CountingActionFeedback"),
    ]


def test_none_is_a_fields_default_as_genpy_takes_it(interfaces):
    header_string = interfaces.message("geometry_msgs/PointStamped")
    made = header_string(None, None)  # genpy: None by position or by name is the field's default
    assert made.header.frame_id == ""
    assert made.point.x == 0.0
    assert header_string(header=None, point=None).to_json()["point"] == {"x": 0.0, "y": 0.0, "z": 0.0}


def test_ros1_header_has_seq_for_rospy(tmp_path):
    ros1 = Interfaces([tmp_path])
    ros1.use_ros1()
    header = ros1.message("std_msgs/Header")
    assert [f.name for f in header._fields] == ["seq", "stamp", "frame_id"]
    stamped = ros1.message("geometry_msgs/PointStamped")()
    stamped.header.stamp.secs, stamped.header.stamp.nsecs = 4, 250
    assert stamped.to_json()["header"] == {"seq": 0, "stamp": {"sec": 4, "nanosec": 250}, "frame_id": ""}
    assert [f.name for f in Interfaces([]).message("std_msgs/Header")._fields] == ["stamp", "frame_id"]  # ROS 2's


def test_a_comment_ends_a_line_and_a_string_constant_keeps_what_follows_its_equals(tmp_path):
    # genmsg and rosidl: a field's comment may hold '=' (still a field, no default); genmsg's string
    # constant is all after its '='; a string default ends at '#' (rosidl cuts every line there)
    kinds = _package(
        tmp_path,
        {"Kinds": b"string name  # a name; '' = a date\nstring TAG=a#b  # kept\nint32 N=3  # n\nstring d 'q # r'\n"},
    ).message("my_pkg/Kinds")
    assert kinds().name == ""
    assert (kinds.TAG, kinds.N) == ("a#b  # kept", 3)
    assert kinds().d == "'q"
    recording = Interfaces([]).get("hri_lab", "srv", "StartRecording")
    assert recording.Request().name == ""  # its comment holds "'' = hri-lab_<date>_<time>"


def _package(tmp_path, files: dict[str, bytes]) -> Interfaces:
    (tmp_path / "my_pkg" / "msg").mkdir(parents=True)
    for name, data in files.items():
        (tmp_path / "my_pkg" / "msg" / f"{name}.msg").write_bytes(data)
    return Interfaces([tmp_path])


def test_a_default_larger_than_the_cap_is_refused_where_it_would_be_built(tmp_path):
    """Fixed arrays of nested messages multiply: 100 x 100 x 100 values would be built by every
    A() (and by the lab for a request that leaves the field out); refused with the line."""
    interfaces = _package(
        tmp_path, {"A": b"int64 n\nB[100] b\n", "B": b"C[100] c\n", "C": b"float64[100] v\n", "Ok": b"C[600] c\n"}
    )
    with pytest.raises(
        DefinitionError, match=r"A.msg, line 2: the default of my_pkg/A would hold more than 65536 values"
    ):
        interfaces.get("my_pkg", "msg", "A")
    assert interfaces.get("my_pkg", "msg", "Ok")._default_values == 60_000  # under the cap: built as before
    assert len(interfaces.get("my_pkg", "msg", "Ok")().c) == 600


def test_recursion_through_another_type_is_named_with_the_cycle(tmp_path):
    interfaces = _package(tmp_path, {"Tree": b"Node root\n", "Node": b"float64 v\nTree[] children\nTree left\n"})
    with pytest.raises(DefinitionError, match=r"contains itself \(my_pkg/Tree -> my_pkg/Node -> my_pkg/Tree\)"):
        interfaces.get("my_pkg", "msg", "Tree")


def test_a_definition_that_is_not_utf8_is_refused_with_its_line(tmp_path):
    interfaces = _package(tmp_path, {"Latin": b"int64 a\nstring caf\xe9\n"})
    with pytest.raises(DefinitionError, match=r"Latin.msg, line 2: not UTF-8 text"):
        interfaces.get("my_pkg", "msg", "Latin")


def test_a_definition_too_long_to_send_is_refused_before_it_is_sent(tmp_path):
    """Each file under the cap, the service with its nested messages over it: full_text (what an
    advertise_service carries) refuses it in the program, not the lab's frame limit on the way."""
    fields = "".join(f"float64 value_{i:05d}_{'x' * 40}\n" for i in range(700)).encode()
    (tmp_path / "my_pkg" / "srv").mkdir(parents=True)
    interfaces = _package(tmp_path, {"Big": fields, "Big2": fields})
    (tmp_path / "my_pkg" / "srv" / "Huge.srv").write_text("Big a\nBig2 b\n---\nBig c\n")
    with pytest.raises(
        DefinitionError, match=r"my_pkg/Huge with its nested messages' is \d+ characters, at most 65536"
    ):
        full_text(interfaces.get("my_pkg", "srv", "Huge"))


def test_available_lists_each_package_of_a_kind_once_with_its_names_sorted(tmp_path):
    """`interface list`'s source: a workspace root's packages beside the shipped ones, a name the two
    roots both define listed once."""
    (tmp_path / "std_msgs" / "msg").mkdir(parents=True)
    (tmp_path / "std_msgs" / "msg" / "String.msg").write_text("string data\n")
    (tmp_path / "lab8" / "srv").mkdir(parents=True)
    for name in ("Zeta", "Alpha"):
        (tmp_path / "lab8" / "srv" / f"{name}.srv").write_text("int64 a\n---\nint64 b\n")
    found = Interfaces([tmp_path])
    assert found.available("msg")["std_msgs"].count("String") == 1
    assert found.available("srv")["lab8"] == ["Alpha", "Zeta"]
    assert "lab8" not in found.available("msg")
    assert list(found.available("srv")) == sorted(found.available("srv"))
