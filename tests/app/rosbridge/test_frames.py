"""The rosbridge endpoint against bad frames and without the token (the real app, in-process
WebSocket): a status message naming the op and field, or a closed socket; never a stuck server
or a stopped simulation."""

import json

import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from app.rosbridge.capabilities.subscribe import MAX_TOPICS
from app.rosbridge.protocol import MAX_DEPTH, MAX_FRAME, MAX_STATUS
from app.serving.compose import create_app
from tests.waiting import wait_for, within


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app()) as c:
        yield c


def exchange(ws, frame) -> dict:
    ws.send_text(frame if isinstance(frame, str) else json.dumps(frame))
    return ws.receive_json()


def call(ws, service, args, id_="c"):
    """A call_service answered (status messages before the response are skipped)."""
    ws.send_json({"op": "call_service", "id": id_, "service": service, "args": args})
    while True:
        message = ws.receive_json()
        if message["op"] == "service_response":
            return message


@pytest.mark.parametrize(
    ("frame", "says"),
    [
        ("{not json", "not a JSON message"),
        ("[1, 2]", "JSON object with an 'op' field"),
        ({"op": 7}, "field 'op' must be a string"),
        ({"op": "explode"}, "unknown op 'explode'"),
        ({"op": "subscribe"}, "subscribe: field 'topic' is required"),
        ({"op": "subscribe", "topic": 5}, "subscribe: field 'topic' must be a string"),
        (
            {"op": "subscribe", "topic": "/joint_states", "throttle_rate": "fast"},
            "field 'throttle_rate' must be an integer",
        ),
        ({"op": "subscribe", "topic": "/joint_states", "type": "std_msgs/String"}, "is of type sensor_msgs/JointState"),
        ({"op": "subscribe", "topic": "/nowhere"}, "topic /nowhere does not exist"),
        ({"op": "publish", "topic": "/joint_states", "msg": {}}, "published by the lab"),
        (
            {"op": "publish", "topic": "/cartesian_velocity_controller/command", "msg": {"linear": {"x": "1"}}},
            "'msg.linear.x' must be a finite number",
        ),
        (
            '{"op": "publish", "topic": "/cartesian_velocity_controller/command", "msg": {"linear": {"x": NaN}}}',
            "'msg.linear.x' must be a finite number",
        ),
        (
            {"op": "publish", "topic": "/cartesian_velocity_controller/command", "msg": {"linear": {}, "speed": 1}},
            "has no field 'speed'",
        ),
        ({"op": "publish", "topic": "/chatter", "msg": {"data": "hi"}}, "advertise /chatter first"),
        ({"op": "advertise_service", "service": "/x"}, "advertise_service: field 'type' is required"),
        (
            {"op": "advertise_service", "service": "/x", "type": "pkg/X", "definition": "int64 a\nint64\n---\n"},
            "the definition of pkg/X cannot be read: <the definition of pkg/srv/X it carried>, line 2: expected 'TYPE NAME'",
        ),
        ({"op": "advertise_service", "service": "/x", "type": "pkg/X", "definition": 3}, "must be a string"),
        (  # the attack suite (docs/operations.md)
            {
                "op": "advertise_service",
                "service": "/cooperative_lifting/set_parameters",
                "type": "rcl_interfaces/SetParameters",
            },
            "is a parameter service of the lab's own node /cooperative_lifting",
        ),
        (
            {"op": "advertise_service", "service": "/big", "type": "p/Big", "definition": "float64[30000000] v\n---\n"},
            "line 1: a fixed-size array of at most 65536 items, got 30000000",
        ),
        (
            {
                "op": "advertise_service",
                "service": "/r",
                "type": "p/R",
                "definition": "p/Node n\n---\n" + "=" * 80 + "\nMSG: p/Node\np/Node next\n",
            },
            "contains itself",
        ),
        ({"op": "call_service", "service": "/add_two_ints", "args": 3}, "field 'args' must be an object"),
        ({"op": "send_action_goal", "action": "/nope", "action_type": "x/Y"}, "action /nope does not exist"),
        ({"op": "cancel_action_goal", "id": "g1", "action": "/count"}, 'no goal with id "g1"'),
        ({"op": "fragment", "id": "f", "data": "{", "num": 0, "total": 2}, "not supported"),
        (
            {
                "op": "subscribe",
                "topic": "/a",
                "type": "x/Y",
                "deep": json.loads("[" * (MAX_DEPTH + 5) + "]" * (MAX_DEPTH + 5)),
            },
            f"nested deeper than {MAX_DEPTH}",
        ),
    ],
)
def test_a_bad_frame_gets_a_status_message_naming_the_field(client, frame, says):
    with client.websocket_connect("/") as ws:
        reply = exchange(ws, frame)
        if reply["op"] == "action_result":  # a goal to a missing action is also answered as failed
            assert reply["result"] is False
            reply = ws.receive_json()
        assert reply["op"] == "status" and reply["level"] == "error", reply
        assert says in reply["msg"], reply["msg"]
        assert call(ws, "/add_two_ints", {"a": 1, "b": 2})["values"] == {"sum": 3}  # the connection goes on


def test_wrong_request_fields_fail_the_call_naming_them(client):
    with client.websocket_connect("/") as ws:
        response = call(ws, "/add_two_ints", {"a": 1, "b": "2"})
        assert response["result"] is False
        assert "b: Input should be a valid integer" in response["values"]
        assert call(ws, "/divide_ints", [7, 2])["values"] == {
            "result": 3.5,
            "message": "Division ok.",
        }  # positional args
        assert call(ws, "/no_such", {})["values"] == "service /no_such does not exist"


def test_a_huge_frame_closes_the_socket_and_the_lab_goes_on(client):
    with client.websocket_connect("/") as ws:
        ws.send_text(json.dumps({"op": "publish", "topic": "/chatter", "msg": {"data": "x" * MAX_FRAME}}))
        assert "limit" in ws.receive_json()["msg"]
        with pytest.raises(WebSocketDisconnect) as closed:
            ws.receive_json()
        assert closed.value.code == 1009
    assert client.get("/health").json()["loop_alive"] is True


def test_a_publish_flood_is_relayed_without_stalling(client):
    """2000 publishes on a node topic, then a call: answered; a subscriber with queue_length 10 gets
    the newest ones, the last of the burst included; the simulation loop still runs."""
    with client.websocket_connect("/") as listener, client.websocket_connect("/") as talker:
        listener.send_json({"op": "subscribe", "topic": "/chatter", "type": "std_msgs/String", "queue_length": 10})
        assert call(listener, "/add_two_ints", {"a": 1, "b": 1})["values"] == {"sum": 2}  # subscribed (ops in order)
        talker.send_json({"op": "advertise", "topic": "/chatter", "type": "std_msgs/String"})
        for i in range(2000):
            talker.send_text(json.dumps({"op": "publish", "topic": "/chatter", "msg": {"data": str(i)}}))
        talker.send_json(
            {
                "op": "publish",
                "topic": "/cartesian_velocity_controller/command",
                "msg": {"linear": {"x": 0, "y": 0, "z": 0}, "angular": {"x": 0, "y": 0, "z": 0}},
            }
        )
        assert call(talker, "/add_two_ints", {"a": 2, "b": 40})["values"] == {"sum": 42}
        received = []
        while "1999" not in received:  # the newest of the burst always arrives, each message at most once
            assert len(received) < 2000, received[-20:]
            message = within(listener.receive_json, 30, f"the listener after {received[-3:]}")
            assert message["op"] == "publish" and message["topic"] == "/chatter", message
            received.append(message["msg"]["data"])
        assert [int(data) for data in received] == sorted(int(data) for data in received)  # in order
    health = client.get("/health").json()
    assert health["loop_alive"] is True
    assert health["step_errors"] == 0
    client.post("/services/error_recovery")  # the one command above may have gone stale


def test_a_throttled_node_topic_still_sends_the_newest_message(client):
    """throttle_rate 500 ms on a node topic: a burst is not cut at its first message; the newest is
    sent once the throttle period has passed (as rosbridge's queue), the ones between may be dropped."""
    with client.websocket_connect("/") as listener, client.websocket_connect("/") as talker:
        listener.send_json({"op": "subscribe", "topic": "/burst", "type": "std_msgs/String", "throttle_rate": 500})
        assert call(listener, "/add_two_ints", {"a": 1, "b": 1})["values"] == {"sum": 2}  # subscribed
        talker.send_json({"op": "advertise", "topic": "/burst", "type": "std_msgs/String"})
        for data in ("first", "second", "newest"):
            talker.send_json({"op": "publish", "topic": "/burst", "msg": {"data": data}})
        received = []
        while "newest" not in received:
            assert len(received) < 3, received
            message = within(listener.receive_json, 30, f"the listener after {received}")
            assert message["op"] == "publish" and message["topic"] == "/burst", message
            received.append(message["msg"]["data"])
        assert received in (["newest"], ["first", "newest"], ["first", "second", "newest"]), received


def test_with_a_token_changes_need_it_reading_does_not():
    with TestClient(create_app(token="s3cret-0123456789abcdef")) as c:
        with c.websocket_connect("/") as ws:
            refused = exchange(
                ws, {"op": "call_service", "id": 1, "service": "/add_two_ints", "args": {"a": 1, "b": 2}}
            )
            assert refused["op"] == "status"
            assert "needs a token" in refused["msg"]
            assert refused["id"] == 1
            refused = exchange(ws, {"op": "advertise_service", "service": "/mine", "type": "std_srvs/Trigger"})
            assert "needs a token" in refused["msg"]
            names = call(ws, "/rosapi/get_param_names", {})["values"]["names"]  # reading stays open
            assert "/cooperative_lifting:mu" in names
            assert (
                "needs a token"
                in exchange(
                    ws,
                    {
                        "op": "call_service",
                        "service": "/rosapi/set_param",
                        "args": {"name": "/cooperative_lifting:mu", "value": "0.6"},
                    },
                )["msg"]
            )
            assert exchange(ws, {"op": "auth", "mac": "wrong"})["msg"] == "auth: wrong token"
            ws.send_json({"op": "auth", "mac": "s3cret-0123456789abcdef"})
            assert call(ws, "/add_two_ints", {"a": 1, "b": 2})["values"] == {"sum": 3}
        with c.websocket_connect("/", headers={"Authorization": "Bearer s3cret-0123456789abcdef"}) as ws:
            assert call(ws, "/add_two_ints", {"a": 1, "b": 2})["values"] == {"sum": 3}


def test_a_definition_other_than_the_declared_one_is_a_warning_and_the_declaration_stays(client):
    """A node that serves a name the lab declares with a .srv of other fields: the lab keeps its
    declaration (type, text, checks) and says so on /rosout and to the node (at level warning); with
    the declared fields, the node's own type and text are shown while it serves the name."""
    with client.websocket_connect("/") as ws:
        ws.send_json({"op": "set_level", "level": "warning"})
        other = {"op": "advertise_service", "service": "/echo", "type": "mine/Echo", "definition": "int64 n\n---\n"}
        ws.send_json(other)
        warning = ws.receive_json()
        assert warning["level"] == "warning"
        assert "/echo is declared by the lab as hri_lab/Echo" in warning["msg"]
        assert client.get("/services/echo").json()["type"] == "hri_lab/Echo"
        assert any("checked against that definition, not mine/Echo's" in e["msg"] for e in client.get("/log").json())
        same = {**other, "type": "mine/srv/Echo", "definition": "# mine\nstring in\n---\nstring out\n"}
        ws.send_json(same)
        info = wait_for(lambda: (i := client.get("/services/echo").json())["type"] == "mine/srv/Echo" and i)
        assert info["srv"] == "# mine\nstring in\n---\nstring out"
    assert wait_for(lambda: client.get("/services/echo").json()["type"] == "hri_lab/Echo")  # it left: the lab's again


def test_a_services_info_names_the_node_that_provides_it_now(client):
    """`GET /services/NAME` names its node as `rosservice info` does: the lab's own, a client's
    while it provides the name, the lab's again once it has left."""
    assert client.get("/services/echo").json()["node"] == "/hri_lab"
    with client.websocket_connect("/") as ws:
        ws.send_json({"op": "advertise_service", "service": "/echo", "type": "hri_lab/Echo"})
        call(ws, "/rosapi/get_time", {})  # ops of a connection are handled in order: advertised now
        node = client.get("/services/echo").json()["node"]
        assert node != "/hri_lab"
        assert node in call(ws, "/rosapi/nodes", {})["values"]["nodes"]
    assert wait_for(lambda: client.get("/services/echo").json()["node"] == "/hri_lab")


def test_what_a_client_sent_is_echoed_cut_short(client):
    """A refused 200 KB type name came back whole in the status message; now at most MAX_STATUS characters of it."""
    with client.websocket_connect("/") as ws:
        bad = {"op": "advertise_service", "service": "/x", "type": "p/" + "X" * 200_000, "definition": "int64\n---\n"}
        reply = exchange(ws, bad)
        assert reply["level"] == "error"
        assert len(reply["msg"]) <= MAX_STATUS + 30
        assert reply["msg"].endswith("characters)")


def test_a_client_subscribes_to_at_most_max_topics(client):
    with client.websocket_connect("/") as ws:
        for i in range(MAX_TOPICS):
            ws.send_json({"op": "subscribe", "topic": f"/t{i}", "type": "std_msgs/String"})
        reply = exchange(ws, {"op": "subscribe", "topic": "/one_more", "type": "std_msgs/String"})
        while reply["op"] != "status":
            reply = ws.receive_json()
        assert f"at most {MAX_TOPICS} topics per client" in reply["msg"]
        ws.send_json({"op": "unsubscribe", "topic": "/t0"})
        ws.send_json({"op": "subscribe", "id": "again", "topic": "/one_more", "type": "std_msgs/String"})
        ws.send_json({"op": "call_service", "id": "c", "service": "/add_two_ints", "args": {"a": 1, "b": 2}})
        seen = []
        while (message := ws.receive_json())["op"] != "service_response":
            seen.append(message)
        assert not [m for m in seen if m.get("level") == "error"], seen  # one topic left: the new one is taken
