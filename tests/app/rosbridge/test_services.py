"""rosbridge's one service table (app/rosbridge/services.py): the lab's services and the nodes',
rosapi's and /republish_tfs, each with one access flag, all called by one path."""

from app.lab.lab import Lab
from app.lab.world import LIFTING
from app.rosbridge import rosapi
from app.rosbridge.capabilities.call_service import CallService
from app.rosbridge.services import ServiceTable
from app.serving.compose import build
from tests.app.rosbridge.clients import connect, op, parts, run

WRITING_ROSAPI = {"/rosapi/set_param", "/rosapi/delete_param"}


def test_every_service_has_one_entry_with_its_type_and_access():
    table = parts(replay=True).bridge.services
    for service in rosapi.SERVICES:
        entry = table.get(service.name)
        assert entry is not None and entry.type.startswith("rosapi/"), service.name
        assert entry.writes == (service.name in WRITING_ROSAPI), service.name
    republish = table.get("/republish_tfs")
    assert republish is not None
    assert republish.type == "tf2_web_republisher/RepublishTFs"
    assert not republish.writes
    lab_service = table.get("/add_two_ints")
    assert lab_service is not None
    assert lab_service.type == "hri_lab/AddTwoInts"
    assert lab_service.writes
    assert table.get("/no_such_service") is None
    assert table.answers_itself("/rosapi/topics")
    assert table.answers_itself("/republish_tfs")
    assert not table.answers_itself("/add_two_ints")


def test_the_names_are_the_labs_offered_services_then_rosapis_then_the_republisher():
    lab = build(LIFTING, Lab(), exercises=True, replay=True)  # the exercises are left to the nodes: not offered yet
    table: ServiceTable = lab.bridge.services.table
    names = table.names()
    rosapi_names = sorted(s.name for s in rosapi.SERVICES)
    assert names[-len(rosapi_names) - 1 :] == [*rosapi_names, "/republish_tfs"]
    assert "/add_two_ints" not in names
    assert "/reset_simulation" in names
    assert table.get("/add_two_ints") is not None  # declared: a call goes to the node that will provide it


def test_one_path_answers_each_kind_of_service():
    async def check() -> None:
        session = await connect(parts(replay=True))
        caller = session.capability(CallService)
        table = session.bridge.services
        assert await table.call(caller, "/add_two_ints", {"a": 2, "b": 3}) == (True, {"sum": 5})
        assert await table.call(caller, "/add_two_ints", [2, 3]) == (True, {"sum": 5})  # fields in order
        ok, reason = await table.call(caller, "/add_two_ints", {"a": "two", "b": 3})
        assert not ok
        assert "a" in reason
        assert await table.call(caller, "/nope", {}) == (False, "service /nope does not exist")
        ok, values = await table.call(caller, "/rosapi/get_time", {})
        assert ok
        assert values["time"]["sec"] == 0
        ok, reason = await table.call(caller, "/republish_tfs", {"source_frames": ["no_such_frame"]})
        assert not ok
        assert "frame 'no_such_frame' does not exist" in reason

    run(check())


def test_a_call_of_a_writing_service_needs_the_token_reading_does_not():
    token = "s3cret-0123456789abcdef"

    async def check() -> None:
        lab = parts(token=token, replay=True)
        stranger, owner = await connect(lab), await connect(lab, token=token)
        for name in ("/add_two_ints", "/rosapi/set_param"):
            refused = await op(stranger, op="call_service", id=1, service=name, args={})
            assert refused[0]["op"] == "status" and "needs a token" in refused[0]["msg"], name
        answer = await op(stranger, op="call_service", service="/rosapi/get_param_names", args={})
        assert answer[0]["result"]
        assert "/cooperative_lifting:mu" in answer[0]["values"]["names"]
        unknown = await op(stranger, op="call_service", service="/nope", args={})
        assert unknown[0] == {
            "op": "service_response",
            "service": "/nope",
            "values": unknown[0]["values"],
            "result": False,
        }
        answer = await op(owner, op="call_service", service="/add_two_ints", args={"a": 1, "b": 2})
        assert answer[0]["values"] == {"sum": 3}

    run(check())
