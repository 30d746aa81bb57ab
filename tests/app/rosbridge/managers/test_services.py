"""Services (app/rosbridge/managers/services.py): the one table a client calls, the lab's registry
as rosapi shows it, and the services nodes provide in it, within the lab's cap (MAX_SERVICES, all
clients together) and gone with their client."""

import pytest

from app.rosbridge.protocol import BadFrame
from tests.app.rosbridge.clients import connect, parts, run


def test_the_table_and_the_registry_as_a_client_sees_them():
    services = parts(replay=True).bridge.services
    assert services.get("/rosapi/topics") is not None and services.answers_itself("/rosapi/topics")
    assert services.get("/add_two_ints") is not None and not services.answers_itself("/add_two_ints")
    assert services.get("/no_such_service") is None
    assert "/add_two_ints" in services.names() and "/republish_tfs" in services.names()
    assert services.provider("/add_two_ints") is None  # the lab answers it
    add = services.service("/add_two_ints")
    assert add is not None and add in list(services.registry())
    assert services.offered("/add_two_ints") and services.lab_provides("/add_two_ints")
    assert services.replaces_lab("/add_two_ints")  # a node advertising it would take it over


def test_a_nodes_service_is_provided_while_its_client_is_there(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr("app.rosbridge.managers.services.MAX_SERVICES", 1)

    async def check() -> None:
        lab = parts(replay=True)
        node, other = await connect(lab), await connect(lab)
        await node.handle('{"op": "node", "name": "/adder"}')
        services = lab.bridge.services
        services.room_for("/mine", "advertise_service")
        assert services.advertise("/mine", "std_srvs/Trigger", node) is None
        assert services.provider("/mine") == "/adder"
        assert services.get("/mine") is not None and "/mine" in services.names()
        assert not services.lab_provides("/mine")
        services.room_for("/mine", "advertise_service")  # its own again: room
        with pytest.raises(BadFrame, match="advertise_service: at most 1 services are provided by nodes already"):
            services.room_for("/yours", "advertise_service")
        assert not services.unadvertise("/mine", other)  # not its
        assert not services.answer(node, "no-such-call", True, {})  # no call waits for it
        services.drop(node)
        assert services.get("/mine") is None and services.provider("/mine") is None
        services.room_for("/yours", "advertise_service")  # room again

    run(check())
