"""sim/recording/reader.py: what a file that is not a recording is said to be, `bag info` from a
finished file's summary and from a file cut short (its messages counted), its `ros2 bag info`
layout, and messages read back by topic, decoded or raw."""

import json

import pytest
from mcap.writer import CompressionType, Writer

from sim.recording.reader import RecordingError, format_info, info, messages, metadata


def write(path, n: int) -> None:
    """n messages on /a (every 0.5 s from t = 10 s), one on /b and a metadata record; a finished file."""
    f = open(path, "wb")  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
    writer = Writer(f, compression=CompressionType.ZSTD, chunk_size=64)
    writer.start(profile="", library="test")
    schema = writer.register_schema("std_msgs/Float64", "jsonschema", b"{}")
    a = writer.register_channel("/a", "json", schema)
    b = writer.register_channel("/b", "json", schema)
    for i in range(n):
        t = 10_000_000_000 + i * 500_000_000
        writer.add_message(a, t, json.dumps({"data": i}).encode(), t)
    writer.add_message(b, 10_000_000_000, b'{"data": -1}', 10_000_000_000)
    writer.add_metadata("run", {"seed": "7", "who": "ada"})
    writer.finish()
    f.close()


@pytest.mark.parametrize(
    ("content", "said"),
    [
        (b"", "an empty file"),
        (b"\x89MC", "a file cut short before its first record"),
        (b"time,f_n\n0,1\n", "a text file"),
        (b"\x00\xff\xfe\x01" * 8, "a binary file of another format"),
    ],
)
def test_a_file_that_is_not_a_recording_is_said_to_be_what_it_is(tmp_path, content, said):
    path = tmp_path / "x.mcap"
    path.write_bytes(content)
    with pytest.raises(RecordingError, match=f"not an MCAP recording \\({said};"):
        info(path)
    with pytest.raises(RecordingError, match="a folder, not an MCAP recording"):
        list(messages(tmp_path))
    with pytest.raises(RecordingError, match="no such file"):
        metadata(tmp_path / "missing.mcap")


def test_bag_info_of_a_finished_file_comes_from_its_summary(tmp_path):
    path = tmp_path / "r.mcap"
    write(path, 5)
    bag = info(path)
    assert bag.complete
    assert bag.messages == 6
    assert (bag.start, bag.end, bag.duration) == (10_000_000_000, 12_000_000_000, 2.0)
    assert [(t.name, t.type, t.count, t.encoding) for t in bag.topics] == [
        ("/a", "std_msgs/Float64", 5, "json"),
        ("/b", "std_msgs/Float64", 1, "json"),
    ]
    text = format_info(bag).splitlines()
    assert text[0] == "Files:             r.mcap"
    assert text[2] == "Storage id:        mcap"
    assert text[3] == "Duration:          2.000s"
    assert text[4].startswith("Start:             Jan 01 1970 00:00:10.000 (10.000)")
    assert text[6] == "Messages:          6"
    assert text[7] == ("Topic information: Topic: /a | Type: std_msgs/Float64 | Count: 5 | Serialization Format: json")
    assert bag.as_dict()["topics"][1] == {"name": "/b", "type": "std_msgs/Float64", "count": 1, "encoding": "json"}
    assert metadata(path)["run"] == {"seed": 7, "who": "ada"}  # JSON values decoded, text kept


def test_a_file_cut_short_is_read_up_to_its_last_chunk_and_says_so(tmp_path):
    whole, cut = tmp_path / "whole.mcap", tmp_path / "cut.mcap"
    write(whole, 40)
    data = whole.read_bytes()
    cut.write_bytes(data[: len(data) // 3])  # no summary, no footer: the writer was killed
    bag = info(cut)
    assert not bag.complete
    assert 0 < bag.messages < 40
    read = [m.data["data"] for m in messages(cut, ["/a"])]
    assert read == list(range(len(read)))  # in order, none invented
    assert "(cut short: no index; read up to the last complete chunk)" in format_info(bag)


def test_messages_are_read_by_topic_decoded_or_raw(tmp_path):
    path = tmp_path / "r.mcap"
    write(path, 3)
    assert [(m.topic, m.data) for m in messages(path, ["/b"])] == [("/b", {"data": -1})]
    raw = list(messages(path, ["/a"], decode=False))
    assert [m.data for m in raw] == [b'{"data": 0}', b'{"data": 1}', b'{"data": 2}']
    assert {m.schema for m in raw} == {"std_msgs/Float64"}
