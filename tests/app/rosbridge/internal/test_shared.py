"""What the streams of one topic share (app/rosbridge/internal/shared.py): a message built once per
topic and time, a frame encoded once per message object, both bounded."""

import base64
import json

import numpy as np

from sim.messages import Base64Text, image

from app.rosbridge.internal.shared import KEEP_BUILT, KEEP_FRAMES, SharedMessages, dumps


def test_a_message_is_built_once_per_topic_and_sample():
    shared, made = SharedMessages(), []

    def make(value):
        made.append(value)
        return {"data": value}

    first = shared.built("/a", 1.0, lambda: make(1))
    assert shared.built("/a", 1.0, lambda: make(2)) is first
    assert made == [1]
    assert shared.built("/b", 1.0, lambda: make(3)) == {"data": 3}  # another topic: its own
    for n in range(KEEP_BUILT):
        shared.built("/a", 2.0 + n, lambda: make(0))
    assert shared.built("/a", 1.0, lambda: make(4)) == {"data": 4}  # the oldest went: made again


def test_a_snapshot_s_trial_changes_when_time_goes_back_so_two_trials_never_share_a_message():
    shared = SharedMessages()
    assert [shared.trial(t) for t in (0.1, 0.2, 0.2, 0.3)] == [0, 0, 0, 0]  # read in order, one trial
    first = shared.built("/a", (shared.trial(0.3), 0.3), lambda: {"trial": 0})
    assert shared.trial(0.1) == 1  # the world was reset
    assert shared.trial(0.3) == 1
    again = shared.built("/a", (shared.trial(0.3), 0.3), lambda: {"trial": 1})
    assert again == {"trial": 1}, "the new trial's snapshot at 0.3 s was given the old trial's message"
    assert first == {"trial": 0}


def test_a_frame_is_encoded_once_per_message_object():
    shared = SharedMessages()
    message = {"data": "x"}
    text = shared.frame("/a", message)
    assert json.loads(text) == {"op": "publish", "topic": "/a", "msg": message}
    assert shared.frame("/a", message) is text
    equal_but_new = {"data": "x"}
    assert shared.frame("/a", equal_but_new) is not text  # another object: encoded for itself
    for n in range(KEEP_FRAMES):
        shared.frame("/a", {"n": n})
    assert len(shared._frames["/a"]) == KEEP_FRAMES
    shared.forget("/a")
    assert "/a" not in shared._frames


def test_an_images_frame_is_json_dumps_text_with_its_base64_put_in_as_it_is():
    """The camera's image (sim/messages.py: its data a Base64Text) encodes to the very text
    json.dumps gives, and reads back as the same message; other frames are json.dumps's."""
    bgr = np.arange(48 * 64 * 3, dtype=np.uint8).reshape(48, 64, 3)
    frame = {"op": "publish", "topic": "/image_raw", "msg": image(1.25, bgr)}
    assert isinstance(frame["msg"]["data"], Base64Text)
    assert dumps(frame) == json.dumps(frame)
    assert base64.b64decode(json.loads(dumps(frame))["msg"]["data"]) == bgr.tobytes()
    plain = {"op": "publish", "topic": "/chatter", "msg": {"data": 'a "quoted"\nline'}}
    assert dumps(plain) == json.dumps(plain)
