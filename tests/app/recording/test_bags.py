"""app/recording/bags.py: a rosbag2 written here is what `rosbags` (and so ROS 2 and Foxglove) reads,
message for message; converted to ROS 1; bags of real robots (rosbags' own writers) read back;
hostile bags refused with their reason."""

import base64

import numpy as np
import pytest
import yaml
from mcap.reader import make_reader
from rosbags.rosbag1 import Reader as Rosbag1Reader
from rosbags.rosbag1 import Writer as Rosbag1Writer
from rosbags.rosbag2 import Reader as Rosbag2Reader
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Rosbag2Writer
from rosbags.typesys import Stores, get_typestore

from sim.recording.reader import RecordingError

from app.recording import bags
from tests import hostile_bags

STUDENT_INFO = "string name\nint32 age\nfloat64[] marks\n"


def _wrench(i: int) -> dict:
    return {
        "header": {"stamp": {"sec": 10 + i, "nanosec": 500}, "frame_id": "panda_link8"},
        "wrench": {"force": {"x": 0.5 * i, "y": -1.0, "z": 12.25}, "torque": {"x": 0.0, "y": 0.125, "z": -i}},
    }


def _image() -> dict:
    pixels = np.arange(2 * 3 * 3, dtype=np.uint8)
    return {
        "header": {"stamp": {"sec": 1, "nanosec": 2}, "frame_id": "camera"},
        "height": 2,
        "width": 3,
        "encoding": "rgb8",
        "is_bigendian": 0,
        "step": 9,
        "data": base64.b64encode(pixels.tobytes()).decode(),
    }


@pytest.fixture
def written(tmp_path):
    """A rosbag2 of the lab's wrench, an image and a program's own StudentInfo (with its definition)."""
    writer = bags.BagWriter(tmp_path / "session", max_bytes=1 << 30)
    writer.add_topic("/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", None)
    writer.add_topic("/image_raw", "sensor_msgs/Image", None)
    writer.add_topic("/student_info", "student_pkg/StudentInfo", STUDENT_INFO)
    sent = []
    for i in range(20):
        t = 1_000_000_000 + i * 1_000_000
        sent.append(("/franka_state_controller/F_ext", t, _wrench(i)))
        sent.append(("/student_info", t, {"name": "ada", "age": i, "marks": [1.5, i / 4]}))
    sent.append(("/image_raw", 1_000_000_000, _image()))
    for topic, t, msg in sent:
        assert writer.write(topic, t, msg)
    writer.close()
    return tmp_path / "session", sent


def test_the_rosbag2_has_ros2s_layout_and_foxglove_encodings(written):
    path, sent = written
    meta = yaml.safe_load((path / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert meta["storage_identifier"] == "mcap"
    assert meta["message_count"] == len(sent)
    with open(path / "session.mcap", "rb") as f:
        mcap = make_reader(f)
        assert mcap.get_header().profile == "ros2"
        summary = mcap.get_summary()
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
    student = next(s for s in summary.schemas.values() if s.name == "student_pkg/msg/StudentInfo")
    assert "float64[] marks" in student.data.decode()  # the program's own definition is in the file


def test_rosbags_reads_back_exactly_what_was_written(written):
    path, sent = written
    with Rosbag2Reader(path) as bag:
        store = get_typestore(Stores.EMPTY)
        got = []
        for connection, t, raw in bag.messages():
            store.register(bags.get_types_from_msg(connection.msgdef.data, connection.msgtype))
            got.append((connection.topic, t, bags.to_json(store.deserialize_cdr(raw, connection.msgtype))))
    key = lambda m: (m[1], m[0])  # noqa: E731 - a one-line sort key
    expected = [(topic, t, _filled(topic, msg)) for topic, t, msg in sent]
    assert sorted(got, key=key) == sorted(expected, key=key)


def _filled(topic: str, msg: dict) -> dict:
    """The message as ROS fills it: every field present, floats as floats."""
    if topic == "/student_info":
        return {"name": msg["name"], "age": msg["age"], "marks": [float(m) for m in msg["marks"]]}
    if topic == "/image_raw":
        return msg
    w = msg["wrench"]
    return {
        "header": msg["header"],
        "wrench": {k: {a: float(v) for a, v in w[k].items()} for k in ("force", "torque")},
    }


def test_open_bag_reads_it_as_rosbridge_json(written):
    path, sent = written
    bag = bags.open_bag(path)
    assert bag.kind == "rosbag2-mcap"
    info = bag.info()
    assert info.messages == len(sent)
    assert {t.name: t.count for t in info.topics}["/student_info"] == 20
    got = [(m.topic, m.log_time, m.data) for m in bag.messages(["/student_info"])]
    assert got == [(t, time, _filled(t, m)) for t, time, m in sent if t == "/student_info"]


def test_converted_to_ros1_the_bag_holds_the_same_messages(written, tmp_path):
    path, sent = written
    assert bags.to_rosbag1(path, tmp_path / "session.bag") == len(sent)
    with Rosbag1Reader(tmp_path / "session.bag") as bag:
        types = {c.topic: c.msgtype for c in bag.connections}
        md5 = {c.topic: c.digest for c in bag.connections}
    assert types["/student_info"] == "student_pkg/msg/StudentInfo"
    assert md5["/franka_state_controller/F_ext"] == "d78d3cb249ce23087ade7e7d0c40cfa7"  # ROS 1's WrenchStamped
    back = bags.open_bag(tmp_path / "session.bag")
    assert back.kind == "rosbag1"
    got = sorted(((m.topic, m.log_time, m.data) for m in back.messages()), key=lambda m: (m[1], m[0]))
    expected = sorted(((t, time, _filled(t, m)) for t, time, m in sent), key=lambda m: (m[1], m[0]))
    for (topic, t, data), (e_topic, e_t, e_data) in zip(got, expected, strict=True):
        assert (topic, t) == (e_topic, e_t)
        if "header" in e_data:  # ROS 1's Header has a seq
            data["header"].pop("seq", None)
        assert data == e_data


def test_a_ros1_bag_from_rosbags_writer_is_read(tmp_path):
    store = get_typestore(Stores.ROS1_NOETIC)
    Point = store.types["geometry_msgs/msg/Point"]
    writer = Rosbag1Writer(tmp_path / "real.bag")
    writer.set_compression(Rosbag1Writer.CompressionFormat.BZ2)  # as real robots' bags often are
    with writer:
        conn = writer.add_connection("/target", "geometry_msgs/msg/Point", typestore=store)
        for i in range(5):
            writer.write(
                conn, 2_000_000_000 + i * 100_000_000, store.serialize_ros1(Point(x=i, y=2.0, z=-1.0), conn.msgtype)
            )
    bag = bags.open_bag(tmp_path / "real.bag")
    assert bag.info().storage == "rosbag1"
    assert [m.data for m in bag.messages()] == [{"x": float(i), "y": 2.0, "z": -1.0} for i in range(5)]


def test_a_sqlite_rosbag2_is_read(tmp_path):
    store = get_typestore(Stores.ROS2_HUMBLE)
    String = store.types["std_msgs/msg/String"]
    with Rosbag2Writer(tmp_path / "db", version=8, storage_plugin=StoragePlugin.SQLITE3) as writer:
        conn = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        writer.write(conn, 5, store.serialize_cdr(String(data="hello"), conn.msgtype))
    bag = bags.open_bag(tmp_path / "db")
    assert bag.kind == "rosbag2-sqlite3"
    assert [(m.topic, m.type, m.data) for m in bag.messages()] == [
        ("/chatter", "std_msgs/msg/String", {"data": "hello"})
    ]


def test_a_rosbag1_bomb_is_refused_before_decompressing(tmp_path):
    with pytest.raises(RecordingError, match=r"a chunk states 1536.0 MiB uncompressed, over the cap of 64 MiB"):
        bags.open_bag(hostile_bags.rosbag1_bomb(tmp_path / "bomb.bag"))


def test_a_rosbag1_chunk_that_states_less_than_it_holds_is_refused(tmp_path):
    with pytest.raises(RecordingError, match="states 100 bytes uncompressed but holds more"):
        bags.open_bag(hostile_bags.rosbag1_bomb(tmp_path / "liar.bag", stated=100, uncompressed=hostile_bags.BLOCK))


@pytest.mark.parametrize(
    ("metadata", "reason"),
    [
        ("rosbag2_bagfile_information: {storage_identifier: mcap, compression_mode: FILE}", "compression mode FILE"),
        ("rosbag2_bagfile_information: {storage_identifier: leveldb}", "storage 'leveldb'"),
        ("just text", "not a rosbag2 metadata.yaml"),
    ],
)
def test_a_rosbag2_folder_that_cannot_be_read_safely_is_named(tmp_path, metadata, reason):
    (tmp_path / "bag").mkdir()
    (tmp_path / "bag" / "metadata.yaml").write_text(metadata)
    with pytest.raises(RecordingError, match=reason):
        bags.open_bag(tmp_path / "bag")


def test_a_definition_that_does_not_parse_is_refused_by_name(tmp_path):
    writer = bags.BagWriter(tmp_path / "b", max_bytes=1 << 20)
    with pytest.raises(RecordingError, match="the definition of student_pkg/msg/Bad does not parse"):
        writer.add_topic("/bad", "student_pkg/Bad", "int32[ broken\n")
    writer.close()


def test_the_size_cap_stops_recording(tmp_path):
    writer = bags.BagWriter(tmp_path / "b", max_bytes=1000)
    writer.add_topic("/image_raw", "sensor_msgs/Image", None)
    assert writer.write("/image_raw", 1, _image())
    big = dict(_image(), data=base64.b64encode(bytes(2000)).decode())
    assert not writer.write("/image_raw", 2, big)
    assert "the cap of 0 MiB" in writer.stopped
    writer.close()
    assert bags.open_bag(tmp_path / "b").info().messages == 1


def test_a_message_that_is_not_its_types_bytes_is_refused_with_the_reason(tmp_path):
    store = get_typestore(Stores.ROS1_NOETIC)
    with Rosbag1Writer(tmp_path / "broken.bag") as writer:
        conn = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        writer.write(conn, 1, b"\xff\xff\xff\x7f")  # a string of 2 GB, in four bytes
    bag = bags.open_bag(tmp_path / "broken.bag")
    with pytest.raises(RecordingError, match=r"broken.bag: a message cannot be read"):
        list(bag.messages())


def test_a_programs_type_with_a_header_converts_to_ros1s_header(tmp_path):
    """A type's ROS 2 text names std_msgs/Header; in the ROS 1 bag it is ROS 1's Header (with seq)."""
    writer = bags.BagWriter(tmp_path / "b", max_bytes=1 << 20)
    writer.add_topic("/stamped", "student_pkg/Stamped", "std_msgs/Header header\nint32 value\n")
    writer.write("/stamped", 7, {"header": {"stamp": {"sec": 3, "nanosec": 4}, "frame_id": "f"}, "value": 9})
    writer.close()
    assert bags.to_rosbag1(tmp_path / "b", tmp_path / "b.bag") == 1
    (message,) = bags.open_bag(tmp_path / "b.bag").messages()
    assert message.data == {"header": {"seq": 0, "stamp": {"sec": 3, "nanosec": 4}, "frame_id": "f"}, "value": 9}


# --- bags as untrusted files: the lab's definition caps, YAML without aliases, SQLite tables first ---
def test_a_rosbag1_whose_definition_holds_a_fixed_array_over_the_cap_is_refused_naming_it(tmp_path):
    path = hostile_bags.rosbag1_with_definition(tmp_path / "evil.bag", "evil/msg/Big", hostile_bags.FIXED_ARRAY)
    with pytest.raises(
        RecordingError, match=r"the definition of evil/msg/Big: a fixed-size array of 100000000 items, over the cap"
    ):
        bags.open_bag(path)


def test_a_variable_length_array_of_messages_of_no_bytes_is_refused(tmp_path):
    data = b"\xff\xff\xff\xff"  # 4 billion empty messages in four bytes
    path = hostile_bags.rosbag1_with_definition(tmp_path / "e.bag", "evil/msg/Seq", hostile_bags.EMPTY_SEQUENCE, data)
    with pytest.raises(RecordingError, match=r"a variable-length array of evil/msg/Empty, a message of no bytes"):
        bags.open_bag(path)


def test_a_default_over_the_cap_of_values_is_refused_naming_the_field(tmp_path):
    text = "evil/Wide[60000] a\nevil/Wide[60000] b\n" + "=" * 80 + "\nMSG: evil/Wide\nint8 x\nint8 y\n"
    path = hostile_bags.rosbag1_with_definition(tmp_path / "wide.bag", "evil/msg/Twice", text)
    with pytest.raises(RecordingError, match=r"the default of evil/msg/Twice would hold more than 65536 values"):
        bags.open_bag(path)


def test_a_type_that_holds_itself_is_refused_and_record_skips_it_with_the_reason(tmp_path):
    path = hostile_bags.rosbag1_with_definition(tmp_path / "loop.bag", "evil/msg/Loop", hostile_bags.SELF_HOLDING)
    with pytest.raises(RecordingError, match=r"type evil/msg/Loop holds itself \(evil/msg/Loop -> evil/msg/Loop\)"):
        bags.open_bag(path)
    writer = bags.BagWriter(tmp_path / "rec", max_bytes=1 << 20)
    with pytest.raises(RecordingError, match="a recursive type"):
        writer.add_topic("/loop", "evil/Loop", hostile_bags.SELF_HOLDING)
    writer.add_topic("/chatter", "std_msgs/String", None)  # the recording goes on
    assert writer.write("/chatter", 1, {"data": "still here"})
    writer.close()


def test_a_metadata_yaml_with_aliases_is_refused_before_it_is_expanded(tmp_path):
    with pytest.raises(RecordingError, match=r"metadata.yaml: YAML aliases \(\*a0\) are not read"):
        bags.open_bag(hostile_bags.billion_laughs(tmp_path / "laughs", levels=4))


def test_a_sqlite_bag_whose_messages_is_a_view_is_refused_before_any_query_of_it(tmp_path):
    with pytest.raises(RecordingError, match=r"evil.db3: 'messages' is a view, not a table"):
        bags.open_bag(hostile_bags.sqlite_view(tmp_path / "view"))
