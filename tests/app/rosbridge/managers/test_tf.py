"""tf (app/rosbridge/managers/tf.py): the lab's /tf carries the programs' frames after its own, a
program's frames go with it, and /republish_tfs makes a topic of the lab's that goes when its
client does."""

import pytest

from app.ros.services import ServiceFailure
from tests.app.rosbridge.clients import connect, parts, run

TRANSFORM = {
    "header": {"frame_id": "world"},
    "child_frame_id": "my_marker",
    "transform": {"translation": {"x": 1.0, "y": 0.0, "z": 0.0}, "rotation": {"x": 0, "y": 0, "z": 0, "w": 1.0}},
}


def children(lab, topic: str) -> set[str]:
    tf_topic = lab.bridge.topics.lab_topic(topic)
    return {t["child_frame_id"] for t in tf_topic.build(lab.lab.snapshot())["transforms"]}


def test_a_programs_frames_join_the_labs_tf_and_go_with_it():
    async def check() -> None:
        lab = parts()
        program = await connect(lab)
        tf = lab.bridge.tf
        own = children(lab, "/tf")
        assert "my_marker" not in own
        assert tf.offer(program, {"transforms": [TRANSFORM]}, static=False) == []
        assert children(lab, "/tf") == own | {"my_marker"}
        assert "my_marker" not in children(lab, "/tf_static")
        lab_frame = {**TRANSFORM, "child_frame_id": sorted(own)[0]}
        assert tf.offer(program, {"transforms": [lab_frame]}, static=False)  # the lab's: refused with a reason
        assert tf.inputs == ("/tf2_web_republisher/goal", "/tf2_web_republisher/cancel")
        tf.drop(program)
        assert children(lab, "/tf") == own

    run(check())


def test_a_republished_topic_is_the_labs_until_it_is_closed():
    async def check() -> None:
        lab = parts()
        client = await connect(lab)
        tf, topics = lab.bridge.tf, lab.bridge.topics
        name, close = tf.republish(client, {"source_frames": ["panda_link8"], "target_frame": "world", "rate": 5.0})
        assert topics.sampled(name) and topics.min_period(name) == pytest.approx(0.2)
        message = topics.lab_topic(name).build(lab.lab.snapshot())
        assert [t["child_frame_id"] for t in message["transforms"]] == ["panda_link8"]
        assert tf.republisher.subscriptions() == 1 and tf.republisher.held_by(client) == 1
        close()
        assert not topics.sampled(name) and tf.republisher.subscriptions() == 0
        with pytest.raises(ServiceFailure, match="frame 'nowhere' does not exist"):
            tf.republish(client, {"source_frames": ["nowhere"]})

    run(check())
