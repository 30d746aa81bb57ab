"""A session (app/rosbridge/session.py) makes one object of every capability for its client, hands
each op to its capability's object, and on close calls each one's finish(): what the client held
(its subscriptions, publishers, services, frames, republished tf topics) leaves the shared state."""

from app.rosbridge.capabilities.advertise_service import AdvertiseService
from app.rosbridge.capabilities.subscribe import Subscribe
from app.rosbridge.ops import CAPABILITIES, OPS
from app.rosbridge.session import Session
from tests.app.rosbridge.clients import connect, op, parts, run, sent

TRANSFORM = {
    "header": {"frame_id": "world"},
    "child_frame_id": "my_marker",
    "transform": {"translation": {"x": 1.0, "y": 0.0, "z": 0.0}, "rotation": {"x": 0, "y": 0, "z": 0, "w": 1.0}},
}


def test_every_op_belongs_to_one_capability_and_every_capability_has_ops():
    assert set(CAPABILITIES) == {o.capability for o in OPS.values()}
    assert {"subscribe", "publish", "call_service", "send_action_goal", "advertise_service"} <= set(OPS)


def test_each_client_has_its_own_capability_objects():
    async def check() -> None:
        lab = parts(replay=True)
        first, second = await connect(lab), await connect(lab)
        assert first.capability(Subscribe) is not second.capability(Subscribe)
        assert first.capability(Subscribe).session is first
        await op(first, op="subscribe", topic="/chatter", type="std_msgs/String")
        assert first.capability(Subscribe).names() == ["/chatter"]
        assert second.capability(Subscribe).names() == []

    run(check())


def test_close_finishes_every_capability_and_the_shared_state_forgets_the_client():
    async def check() -> None:
        lab = parts()
        bridge = lab.bridge
        session = await connect(lab)
        await op(session, op="subscribe", topic="/chatter", type="std_msgs/String")
        await op(session, op="advertise", topic="/chatter", type="std_msgs/String")
        await op(session, op="advertise_service", service="/mine", type="std_srvs/Trigger")
        await op(session, op="advertise", topic="/tf", type="tf2_msgs/TFMessage")
        await op(session, op="publish", topic="/tf", msg={"transforms": [TRANSFORM]})
        answer = await op(
            session, op="call_service", service="/republish_tfs", args={"source_frames": ["my_marker"], "rate": 5.0}
        )
        topic = answer[-1]["values"]["topic_name"]
        assert session.details() == {
            "subscribing": ["/chatter"],
            "publishing": ["/chatter", "/tf"],
            "services": ["/mine"],
        }
        assert bridge.topics.find("/chatter") is not None
        assert bridge.services.get("/mine") is not None
        assert "my_marker" in bridge.tf.frames.names()
        assert bridge.topics.sampled(topic)
        assert bridge.topics.streams == 1
        await session.close()
        assert session not in bridge.sessions.all()
        assert bridge.topics.find("/chatter") is None
        assert bridge.topics.streams == 0
        assert bridge.services.get("/mine") is None
        assert not bridge.services.nodes.providers
        assert "my_marker" not in bridge.tf.frames.names()
        assert not bridge.topics.sampled(topic)
        assert session.capability(AdvertiseService).names() == []

    run(check())


def test_an_unknown_op_or_a_bad_frame_is_a_status_and_the_connection_goes_on():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert (await op(session, op="teleport", id=7)) == [
            {"op": "status", "level": "error", "msg": "unknown op 'teleport'", "id": 7}
        ]
        await session.handle("[1, 2")
        assert "not a JSON message" in sent(session, "status")[-1]["msg"]
        assert (await op(session, op="subscribe", topic="/chatter", type="std_msgs/String")) == []

    run(check())


def test_with_a_token_a_mutating_op_needs_it():
    token = "s3cret-0123456789abcdef"

    async def check() -> None:
        lab = parts(token=token, replay=True)
        stranger, owner = await connect(lab), await connect(lab, token=token)
        refused = await op(stranger, op="advertise", topic="/chatter", type="std_msgs/String", id=1)
        assert refused[0]["level"] == "error"
        assert "advertise: this lab needs a token" in refused[0]["msg"]
        assert lab.bridge.topics.find("/chatter") is None
        assert await op(owner, op="advertise", topic="/chatter", type="std_msgs/String") == []
        assert lab.bridge.topics.find("/chatter") is not None
        assert await op(stranger, op="subscribe", topic="/chatter") == []  # reading is open

    run(check())


def test_a_sessions_name_is_its_first_node_else_its_client_name():
    async def check() -> None:
        session: Session = await connect(parts(replay=True))
        assert session.name.startswith("/rosbridge_client_")
        await op(session, op="node", name="/talker")
        await op(session, op="node", name="/listener")
        assert session.name == "/talker"
        assert session.node_names == ["/talker", "/listener"]

    run(check())
