"""advertise_service / unadvertise_service (app/rosbridge/capabilities/advertise_service.py): a
client provides a service in the lab's registry; every caller reaches it; rosbridge's own services
and the lab node's parameter services are not a client's to provide; the services go with it."""

from app.rosbridge.capabilities.advertise_service import AdvertiseService
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_another_clients_call_reaches_the_provider_and_its_answer_comes_back():
    async def check() -> None:
        lab = parts(replay=True)
        provider, caller = await connect(lab), await connect(lab)
        await op(provider, op="node", name="/greeter")
        assert await op(provider, op="advertise_service", service="/greet", type="std_srvs/Trigger") == []
        assert lab.bridge.services.get("/greet") is not None
        await caller.handle('{"op": "call_service", "id": "hi", "service": "/greet", "args": {}}')
        request = (await until(lambda: sent(provider, "call_service"), "the call at its provider"))[0]
        assert request["service"] == "/greet"
        assert request["args"] == {}
        answer = {"success": True, "message": "hello"}
        await op(provider, op="service_response", id=request["id"], service="/greet", values=answer, result=True)
        response = (await until(lambda: sent(caller, "service_response"), "the answer at the caller"))[0]
        assert response["values"] == answer
        assert response["result"] is True
        assert response["id"] == "hi"

    run(check())


def test_rosbridges_own_services_and_the_lab_nodes_parameter_services_are_refused():
    async def check() -> None:
        session = await connect(parts(replay=True))
        for name in ("/rosapi/topics", "/republish_tfs"):
            refused = await op(session, op="advertise_service", service=name, type="std_srvs/Trigger")
            assert refused[0]["msg"] == f"advertise_service: {name} is the lab's", name
        refused = await op(session, op="advertise_service", service="/cooperative_lifting/get_parameters", type="a/B")
        assert "parameter service of the lab's own node /cooperative_lifting" in refused[0]["msg"]

    run(check())


def test_replacing_a_labs_own_service_is_warned_and_finish_gives_it_back():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        warned = await op(session, op="advertise_service", service="/add_two_ints", type="hri_lab/AddTwoInts")
        assert warned[-1]["level"] == "warning"
        assert "one of the lab's own services" in warned[-1]["msg"]
        assert lab.bridge.services.nodes.goes_to_node("/add_two_ints")
        session.capability(AdvertiseService).finish()
        assert not lab.bridge.services.nodes.goes_to_node("/add_two_ints")
        assert session.capability(AdvertiseService).names() == []

    run(check())


def test_unadvertise_withdraws_only_the_clients_own():
    async def check() -> None:
        lab = parts(replay=True)
        first, second = await connect(lab), await connect(lab)
        await op(first, op="advertise_service", service="/mine", type="std_srvs/Trigger")
        await op(second, op="set_level", level="warning")
        refused = await op(second, op="unadvertise_service", service="/mine")
        assert "not provided by this client" in refused[0]["msg"]
        assert lab.bridge.services.get("/mine") is not None
        await op(first, op="unadvertise_service", service="/mine")
        assert lab.bridge.services.get("/mine") is None

    run(check())
