"""The program's connection (rosclient/connection.py): a publish frame in the lab's shape is
handed to an `undecoded` handler as its bytes, its topic read without decoding it; the taker
decodes it (`message_of`); every frame reads as the standard library reads it (`decode`)."""

import json

import pytest

from app.rosbridge.internal.shared import dumps
from rosclient.connection import Frame, _publish_topic, decode, framed, message_of, sender_of


def test_the_topic_of_a_labs_publish_frame_is_read_without_decoding_it():
    frame = dumps({"op": "publish", "topic": "/image_raw", "msg": {"data": "AQI="}}).encode()  # the lab's encoder
    assert _publish_topic(frame) == "/image_raw"
    assert message_of(frame) == {"data": "AQI="}
    assert message_of({"data": "x"}) == {"data": "x"}  # decoded already for another handler


def test_a_frames_publisher_is_read_from_its_connection_header_and_the_frame_decoded_once():
    """rclpy's subscriptions ask for connection headers (the program that sent a message: its `callerid`)."""
    message = {"data": "hi"}
    frame = dumps({"op": "publish", "topic": "/chatter", "msg": message, "connection_header": {"callerid": "/talker"}})
    assert _publish_topic(frame.encode()) == "/chatter"  # the header comes after the message
    assert sender_of(frame.encode()) == "/talker"
    once = framed(frame.encode())
    assert isinstance(once, Frame) and sender_of(once) == "/talker" and message_of(once) == message
    without = dumps({"op": "publish", "topic": "/chatter", "msg": message}).encode()
    assert sender_of(without) is None and sender_of(message) is None  # no header; a message itself
    assert sender_of(b"{") is None and framed(b"{") == b"{"  # not JSON: left as it came


def test_any_other_frame_is_left_to_the_usual_decoding():
    assert _publish_topic(json.dumps({"op": "call_service", "service": "/a", "id": "1"}).encode()) is None
    assert _publish_topic(b'{"topic": "/a", "op": "publish", "msg": {}}') is None  # another shape
    assert _publish_topic(b'{"op": "publish", "topic": "/a\\"b", "msg": {}}') is None  # an escape in the name
    assert _publish_topic(b'{"op": "publish", "topic": "/a", "connection_header": {}}') is None
    assert _publish_topic(b'{"op": "publish", "topic": "/\xff", "msg": {}}') is None  # not UTF-8
    assert message_of(b'{"op": "publish", "topic": "/a", "msg": {') is None  # not JSON: nothing to take


@pytest.mark.parametrize(
    "text",
    [
        '{"op": "publish", "topic": "/f", "msg": {"x": 1.5, "s": "\\u00e9t\\u00e9", "l": [1, -2, 3e-7]}}',
        '{"msg": {"force": {"x": NaN, "y": Infinity, "z": -Infinity}}}',  # json.dumps writes them
        '{"u64": 18446744073709551615, "i64": -9223372036854775808}',  # a uint64's and an int64's ends
    ],
)
def test_a_frame_reads_as_the_standard_library_reads_it(text):
    expected = json.loads(text)
    for frame in (text, text.encode()):
        got = decode(frame)
        assert json.dumps(got) == json.dumps(expected)  # NaN == NaN as text


def test_an_integer_beyond_64_bits_which_no_ros_field_holds_is_read_as_a_float():
    assert decode(b'{"n": 18446744073709551616}') == {"n": 18446744073709551616.0}


@pytest.mark.parametrize(
    ("frame", "reason"),
    [
        (b'{"op": ', "Expecting value"),
        (b'{"a": "\xff"}', "can't decode byte 0xff"),  # not UTF-8
        ("{'a': 1}", "Expecting property name"),
    ],
)
def test_what_is_not_json_is_a_value_error(frame, reason):
    with pytest.raises(ValueError, match=reason):  # the reader and message_of skip it
        decode(frame)
