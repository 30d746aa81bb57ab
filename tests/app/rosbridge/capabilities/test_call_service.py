"""call_service (app/rosbridge/capabilities/call_service.py): any service of the one table, answered
with service_response; a failed call is result false with its reason; a client's calls in flight
are bounded; what a call left for the client (a republished tf topic) goes with it."""

import asyncio
import json

from app.ros.names import LAB_NODE
from app.rosbridge.capabilities.call_service import MAX_CALLS_IN_FLIGHT, CallService
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_a_call_is_answered_with_its_id_a_failure_with_its_reason():
    async def check() -> None:
        session = await connect(parts(replay=True))
        answer = await op(session, op="call_service", id="c1", service="/add_two_ints", args={"a": 1, "b": 2})
        assert answer == [
            {"op": "service_response", "service": "/add_two_ints", "values": {"sum": 3}, "result": True, "id": "c1"}
        ]
        failed = await op(session, op="call_service", id="c2", service="/add_two_ints", args={"a": 2**62, "b": 2**62})
        assert failed[0]["result"] is False
        assert failed[0]["id"] == "c2"
        assert failed[1]["op"] == "status"
        assert failed[1]["msg"] == f"call_service /add_two_ints: {failed[0]['values']}"
        bad = await op(session, op="call_service", service="/add_two_ints", args="1 2")
        assert "field 'args' must be an object" in bad[0]["msg"]

    run(check())


def test_calls_in_flight_are_bounded_per_client():
    async def check() -> None:
        session = await connect(parts(replay=True))
        session.in_flight = MAX_CALLS_IN_FLIGHT  # as many as may be served at once
        refused = await op(session, op="call_service", service="/rosapi/get_time")
        assert f"{MAX_CALLS_IN_FLIGHT} calls of this client are already in flight" in refused[0]["msg"]
        session.in_flight = 0
        assert (await op(session, op="call_service", service="/rosapi/get_time"))[0]["result"] is True
        assert session.in_flight == 0  # given back when answered

    run(check())


def test_a_republished_tf_topic_goes_with_its_client():
    async def check() -> None:
        lab = parts()
        session = await connect(lab)
        answer = await op(session, op="call_service", service="/republish_tfs", args={"source_frames": ["panda_link8"]})
        topic = answer[0]["values"]["topic_name"]
        assert lab.bridge.topics.sampled(topic)
        assert len(session.capability(CallService).on_close) == 1
        await session.close()
        assert not lab.bridge.topics.sampled(topic)
        await asyncio.sleep(0)
        assert sent(session, "status") == []

    run(check())


def test_a_call_with_headers_reaches_the_node_with_the_callers_and_returns_the_servers():
    async def check() -> None:
        lab = parts(replay=True)
        provider, caller, plain = await connect(lab), await connect(lab), await connect(lab)
        await op(provider, op="node", name="/add_two_ints_server")
        await op(provider, op="advertise_service", service="/greet", type="std_srvs/Trigger")
        await op(caller, op="node", name="/client")
        frame = {"op": "call_service", "id": "hi", "service": "/greet", "args": {}, "headers": {"cookies": "peanut"}}
        await caller.handle(json.dumps(frame))
        await plain.handle(json.dumps({"op": "call_service", "id": "plain", "service": "/greet", "args": {}}))
        await until(lambda: sent(provider, "call_service")[1:], "both calls at the provider")
        requests = sent(provider, "call_service")
        headers = {r["id"]: r["connection_header"] for r in requests}
        assert sorted(headers.values(), key=len) == [
            {"callerid": plain.client_name},  # a rosbridge client's call: its name, no fields of its own
            {"callerid": "/client", "cookies": "peanut"},
        ]
        for request in requests:
            answer = {"success": True, "message": "hello"}
            await op(provider, op="service_response", id=request["id"], service="/greet", values=answer, result=True)
        response = (await until(lambda: sent(caller, "service_response"), "the answer at the caller"))[0]
        assert response["connection_header"] == {"callerid": "/add_two_ints_server"}
        plain_response = (await until(lambda: sent(plain, "service_response"), "the plain answer"))[0]
        assert "connection_header" not in plain_response  # rosbridge's frame for a client that gave none
        # a service the lab answers: the lab's own node
        own = await op(caller, op="call_service", service="/rosapi/get_time", headers={})
        assert own[0]["connection_header"] == {"callerid": LAB_NODE}

    run(check())
