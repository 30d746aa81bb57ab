"""service_response (app/rosbridge/capabilities/service_response.py): an answer no call of this
client's services waits for is a warning, and changes nothing."""

from tests.app.rosbridge.clients import connect, op, parts, run


def test_an_answer_nobody_waits_for_is_a_warning():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert await op(session, op="service_response", id="lab:/x:1", values={}, result=True) == []  # level error
        await op(session, op="set_level", level="warning")
        warned = await op(session, op="service_response", id="lab:/x:1", values={}, result=True)
        assert warned[0]["level"] == "warning"
        assert 'no call with id "lab:/x:1" waits' in warned[0]["msg"]

    run(check())
