"""The program's connection (app/rosclient/connection.py): a publish frame in the lab's shape is
handed to an `undecoded` handler as its text, its topic read without decoding it; the taker
decodes it (`message_of`)."""

import json

from app.rosbridge.internal.shared import dumps
from app.rosclient.connection import _publish_topic, message_of


def test_the_topic_of_a_labs_publish_frame_is_read_without_decoding_it():
    frame = dumps({"op": "publish", "topic": "/image_raw", "msg": {"data": "AQI="}})  # the lab's encoder
    assert _publish_topic(frame) == "/image_raw"
    assert message_of(frame) == {"data": "AQI="}
    assert message_of({"data": "x"}) == {"data": "x"}  # decoded already for another handler


def test_any_other_frame_is_left_to_the_usual_decoding():
    assert _publish_topic(json.dumps({"op": "call_service", "service": "/a", "id": "1"})) is None
    assert _publish_topic('{"topic": "/a", "op": "publish", "msg": {}}') is None  # another shape
    assert _publish_topic('{"op": "publish", "topic": "/a\\"b", "msg": {}}') is None  # an escape in the name
    assert _publish_topic('{"op": "publish", "topic": "/a", "connection_header": {}}') is None
    assert message_of('{"op": "publish", "topic": "/a", "msg": {') is None  # not JSON: nothing to take
