"""The node op (app/rosbridge/capabilities/node.py): a client's node names are what rosapi, a
service's info, errors and /rosout show; a bad or the lab's own name is refused naming the field."""

import pytest
from fastapi.testclient import TestClient

from app.rosbridge.capabilities.node import MAX_NODES
from app.serving.compose import create_app
from tests.app.rosbridge.clients import connect, op, parts, run
from tests.waiting import wait_for, within


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app()) as c:
        yield c


def call(ws, service: str, args: dict, call_id: str = "c") -> dict:
    ws.send_json({"op": "call_service", "id": call_id, "service": service, "args": args})
    while (message := within(ws.receive_json, 30, f"the answer of {service}"))["op"] != "service_response":
        pass
    return message


def test_a_named_node_is_what_rosapi_services_and_rosout_show(client):
    with client.websocket_connect("/") as ws:
        ws.send_json({"op": "node", "name": "/tutorial/talker"})
        ws.send_json({"op": "node", "name": "/tutorial/listener"})  # a second node of the same program
        ws.send_json({"op": "advertise_service", "service": "/named_echo", "type": "std_srvs/Trigger"})
        nodes = call(ws, "/rosapi/nodes", {})["values"]["nodes"]
        assert "/tutorial/talker" in nodes
        assert "/tutorial/listener" in nodes
        assert not any(n.startswith("/rosbridge_client_") for n in nodes)
        details = call(ws, "/rosapi/node_details", {"node": "/tutorial/listener"})["values"]
        assert details["services"] == ["/named_echo"]
        assert client.get("/services/named_echo").json()["node"] == "/tutorial/talker"
        ws.send_json({"op": "advertise", "topic": "/rosout", "type": "rosgraph_msgs/Log"})
        ws.send_json({"op": "publish", "topic": "/rosout", "msg": {"level": 2, "msg": "hello from a named node"}})
        logged = wait_for(lambda: [e for e in client.get("/log").json() if e["msg"] == "hello from a named node"])
        assert logged[0]["node"] == "/tutorial/talker"
    assert wait_for(lambda: client.get("/services/named_echo").status_code == 404)  # gone with its node


def test_a_second_provider_is_refused_naming_the_node_that_has_the_name(client):
    with client.websocket_connect("/") as first, client.websocket_connect("/") as second:
        first.send_json({"op": "node", "name": "/first_server"})
        first.send_json({"op": "advertise_service", "service": "/taken", "type": "std_srvs/Trigger"})
        call(first, "/rosapi/get_time", {})
        second.send_json({"op": "advertise_service", "id": "again", "service": "/taken", "type": "std_srvs/Trigger"})
        refusal = within(second.receive_json, 30, "the refusal")
        assert refusal["id"] == "again"
        assert "already provided by node /first_server" in refusal["msg"]


@pytest.mark.parametrize(
    ("name", "says"),
    [
        ("/hri_lab", "node: /hri_lab is the lab's own node"),
        ("/bad name", "field 'name' must be a ROS name"),
        ("/1talker", "field 'name' must be a ROS node name"),
        (7, "field 'name'"),
    ],
)
def test_a_bad_node_name_is_refused_naming_the_field(client, name, says):
    with client.websocket_connect("/") as ws:
        ws.send_json({"op": "node", "id": "n", "name": name})
        refusal = within(ws.receive_json, 30, "the refusal")
        assert refusal["op"] == "status" and says in refusal["msg"], refusal
        nodes = call(ws, "/rosapi/nodes", {})["values"]["nodes"]
        assert nodes.count("/hri_lab") == 1
        assert any(n.startswith("/rosbridge_client_") for n in nodes)


def test_a_bad_name_or_the_labs_own_is_refused_naming_the_field():
    async def check() -> None:
        session = await connect(parts(replay=True))
        bad = await op(session, op="node", name="/9lives")
        assert bad[0]["msg"].startswith("node: field 'name' must be a ROS node name")
        assert (await op(session, op="node", name="/hri_lab"))[0]["msg"] == "node: /hri_lab is the lab's own node"
        for n in range(MAX_NODES):
            await op(session, op="node", name=f"/n{n}")
        assert f"at most {MAX_NODES} nodes" in (await op(session, op="node", name="/one_more"))[0]["msg"]
        assert await op(session, op="node", name="/n0") == []  # named already: nothing to do

    run(check())
