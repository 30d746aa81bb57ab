"""rosapi (app/rosbridge/rosapi.py): a table of handlers, each answered from the lab's registries."""

import json

from sim.controllers.interface import LiftingParams

from app.mobile.lab import MobileLab
from app.mobile.world import MOBILE
from app.rosbridge import rosapi
from app.rosbridge.capabilities.call_service import CallService
from app.serving.compose import build as parts_of
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_the_table_names_each_service_once_and_only_parameters_change_the_lab():
    names = [s.name for s in rosapi.SERVICES]
    assert len(names) == len(set(names)) == 23
    assert all(name.startswith("/rosapi/") for name in names)
    assert {s.name for s in rosapi.SERVICES if s.writes} == {"/rosapi/set_param", "/rosapi/delete_param"}


def test_topics_services_and_types_are_the_labs():
    async def check() -> None:
        lab = parts()
        session = await connect(lab)
        caller = session.capability(CallService)
        table = lab.bridge.services

        async def values(name: str, **args: object) -> dict:
            ok, answer = await table.call(caller, name, args)
            assert ok, answer
            return answer

        topics = await values("/rosapi/topics")
        assert dict(zip(topics["topics"], topics["types"]))["/joint_states"] == "sensor_msgs/JointState"
        assert "/rosout" in topics["topics"]
        assert (await values("/rosapi/topic_type", topic="joint_states"))["type"] == "sensor_msgs/JointState"
        assert (await values("/rosapi/services"))["services"] == table.names()
        assert (await values("/rosapi/service_type", service="/divide_ints"))["type"] == "hri_lab/DivideInts"
        assert (await values("/rosapi/service_type", service="/rosapi/topics"))["type"] == "rosapi/Topics"
        request = (await values("/rosapi/service_request_details", type="hri_lab/AddTwoInts"))["typedefs"][0]
        assert request["fieldnames"] == ["a", "b"]
        assert request["fieldtypes"] == ["int64", "int64"]
        lab_node = await values("/rosapi/node_details", node="/hri_lab")
        assert "/add_two_ints" in lab_node["services"]
        assert "/joint_states" in lab_node["publishing"]
        assert (await values("/rosapi/publishers", topic="/joint_states"))["publishers"] == ["/hri_lab"]
        await op(session, op="node", name="/listener")
        await op(session, op="subscribe", topic="/chatter", type="std_msgs/String")
        assert (await values("/rosapi/subscribers", topic="/chatter"))["subscribers"] == ["/listener"]
        command = lab.bridge.topics.command_topic  # the lab's own subscriber, as get_num_connections counts it
        assert (await values("/rosapi/subscribers", topic=command))["subscribers"] == ["/hri_lab"]
        assert "/listener" in (await values("/rosapi/nodes"))["nodes"]
        assert (await values("/rosapi/node_details", node="/listener"))["subscribing"] == ["/chatter"]
        assert "/count" in (await values("/rosapi/action_servers"))["action_servers"]

    run(check())


def test_parameters_by_rosapis_two_kinds_of_names():
    async def check() -> None:
        lab = parts(replay=True)
        caller = (await connect(lab)).capability(CallService)
        table = lab.bridge.services
        alpha = await table.call(caller, "/rosapi/get_param", {"name": "/cooperative_lifting:alpha"})
        assert alpha == (True, {"value": json.dumps(LiftingParams().alpha)})
        assert await table.call(
            caller, "/rosapi/set_param", {"name": "/cooperative_lifting:alpha", "value": "0.6"}
        ) == (
            True,
            {},
        )
        assert lab.lab.params.get("cooperative_lifting", "alpha") == 0.6
        assert await table.call(caller, "/rosapi/set_param", {"name": "/my/gain", "value": "2"}) == (True, {})
        assert await table.call(caller, "/rosapi/get_param", {"name": "/my/gain"}) == (True, {"value": "2"})
        assert await table.call(caller, "/rosapi/has_param", {"name": "/my/gain"}) == (True, {"exists": True})
        ok, reason = await table.call(caller, "/rosapi/set_param", {"name": "/my/gain", "value": "not json"})
        assert not ok
        assert "'value' must be JSON text" in reason
        ok, reason = await table.call(caller, "/rosapi/delete_param", {"name": "/cooperative_lifting:alpha"})
        assert not ok
        assert "declared by its node" in reason

    run(check())


def test_the_mobile_worlds_cmd_vel_is_published_by_the_nodes_alone():
    """The lab follows /cmd_vel and never publishes it (as Gazebo's diff drive): `rostopic info`
    names the nodes that drive the base, a leftover one as a second publisher; what the base follows
    is the lab's own /cmd_vel_followed."""

    async def check() -> None:
        lab = parts_of(MOBILE, MobileLab(realtime=False))
        follower, leftover, listener = [await connect(lab) for _ in range(3)]
        for session, name in ((follower, "/follower"), (leftover, "/leftover"), (listener, "/listener")):
            await op(session, op="node", name=name)
        caller = listener.capability(CallService)

        async def values(name: str, **args: object) -> dict:
            ok, answer = await lab.bridge.services.call(caller, name, args)
            assert ok, answer
            return answer

        assert (await values("/rosapi/publishers", topic="/cmd_vel"))["publishers"] == []
        assert (await values("/rosapi/subscribers", topic="/cmd_vel"))["subscribers"] == ["/hri_lab"]
        topics = await values("/rosapi/topics")
        # in the graph as the base's subscription puts it there (rosapi's topics are the master's getTopicTypes)
        assert dict(zip(topics["topics"], topics["types"]))["/cmd_vel"] == "geometry_msgs/Twist"
        assert dict(zip(topics["topics"], topics["types"]))["/cmd_vel_followed"] == "geometry_msgs/Twist"
        assert (await values("/rosapi/publishers", topic="/cmd_vel_followed"))["publishers"] == ["/hri_lab"]
        assert "/cmd_vel" not in (await values("/rosapi/node_details", node="/hri_lab"))["publishing"]
        await op(listener, op="subscribe", topic="/cmd_vel", type="geometry_msgs/Twist")
        for session in (follower, leftover):
            await op(session, op="advertise", topic="/cmd_vel", type="geometry_msgs/Twist")
        assert (await values("/rosapi/publishers", topic="/cmd_vel"))["publishers"] == ["/follower", "/leftover"]
        await op(follower, op="publish", topic="/cmd_vel", msg={"linear": {"x": 0.1}, "angular": {"z": 0.5}})
        await until(lambda: sent(listener, "publish"), "the follower's twist at /cmd_vel's subscriber")
        assert sent(listener, "publish")[0]["msg"]["angular"]["z"] == 0.5
        await until(lambda: lab.bridge.lab.world.command[1] == 0.5, "the twist followed by the base")
        await op(leftover, op="unadvertise", topic="/cmd_vel")
        assert (await values("/rosapi/publishers", topic="/cmd_vel"))["publishers"] == ["/follower"]

    run(check())


def test_endpoints_a_client_told_are_listed_with_their_nodes_and_qos():
    """The lab's `endpoints` op (capabilities/endpoints.py) and `/rosapi/endpoints`: each entity of a
    kind on a name as its client told it, gone when it tells none or leaves; bad input refused by name."""

    async def check() -> None:
        lab = parts()
        program, other = await connect(lab), await connect(lab)
        caller = program.capability(CallService)
        table = lab.bridge.services.table
        qos = {"reliability": "BEST_EFFORT", "durability": "VOLATILE", "deadline": 0}
        entities = [{"node": "/talker", "qos": qos}, {"node": "/talker2", "qos": {}}]
        assert await op(program, op="endpoints", kind="publisher", name="chatter", entities=entities) == []
        await op(other, op="endpoints", kind="client", name="/add_two_ints", entities=[{"node": "/caller", "qos": {}}])
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "publisher", "name": "/chatter"})
        assert ok and answer["endpoints"] == entities
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "client", "name": "/add_two_ints"})
        assert [e["node"] for e in answer["endpoints"]] == ["/caller"]
        await op(other, op="node", name="/echo")  # a client that tells none: one entity, its QoS unknown
        await op(other, op="subscribe", topic="/chatter", type="std_msgs/String")
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "subscription", "name": "/chatter"})
        assert answer["endpoints"] == [{"node": "/echo", "qos": {}}]
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "publisher", "name": "/joint_states"})
        assert answer["endpoints"] == [{"node": "/hri_lab", "qos": {}}]
        await op(program, op="endpoints", kind="publisher", name="/chatter", entities=[])
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "publisher", "name": "/chatter"})
        assert answer["endpoints"] == []
        await other.close()
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "client", "name": "/add_two_ints"})
        assert answer["endpoints"] == []
        ok, reason = await table.call(caller, "/rosapi/endpoints", {"kind": "reader", "name": "/chatter"})
        assert not ok and "one of publisher, subscription, client, action_client, action_server" in reason
        # an action's server is never told: the lab's node serves its own, the providing client's node a node's
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "action_server", "name": "/count"})
        assert answer["endpoints"] == [{"node": "/hri_lab", "qos": {}}]
        await op(program, op="node", name="/demo/talker")
        await op(program, op="advertise_action", action="/fibonacci", type="example_interfaces/action/Fibonacci")
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "action_server", "name": "fibonacci"})
        assert [e["node"] for e in answer["endpoints"]] == ["/demo/talker"]
        ok, answer = await table.call(caller, "/rosapi/endpoints", {"kind": "action_server", "name": "/nothing"})
        assert answer["endpoints"] == []
        refusals = {
            "endpoints: field 'kind' must be one of publisher, subscription, client, action_client, got 'reader'": {
                "kind": "reader"
            },
            "endpoints: field 'kind' must be one of publisher, subscription, client, action_client, got "
            "'action_server'": {"kind": "action_server"},
            "endpoints: an entity's 'node' must be a node's full name, e.g. /talker": {"entities": [{"node": "x"}]},
            "endpoints: qos field 'deadline' must be a name or a finite number": {
                "entities": [{"node": "/a", "qos": {"deadline": [1]}}]
            },
        }
        for reason, fields in refusals.items():
            frame = {"op": "endpoints", "kind": "publisher", "name": "/chatter", "entities": [], **fields}
            assert (await op(program, **frame))[0]["msg"] == reason

    run(check())
