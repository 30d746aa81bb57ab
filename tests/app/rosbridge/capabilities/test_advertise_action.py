"""advertise_action and the provider's answers (app/rosbridge/capabilities/advertise_action.py): a
client's action in the lab's ActionServer, its goals sent to it, its feedback and result taken
back; the action goes with its client."""

from app.rosbridge.capabilities.advertise_action import AdvertiseAction
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_a_goal_reaches_the_provider_and_its_result_ends_the_goal():
    async def check() -> None:
        lab = parts(replay=True)
        provider, client = await connect(lab), await connect(lab)
        assert await op(provider, op="advertise_action", action="/tally", type="hri_lab/Count") == []
        assert lab.bridge.actions.get("/tally") is not None
        await client.handle('{"op": "send_action_goal", "id": "t", "action": "/tally", "args": {"count": 2}}')
        goal = (await until(lambda: sent(provider, "send_action_goal"), "the goal at its provider"))[0]
        assert goal["args"] == {"count": 2}
        await op(provider, op="action_feedback", id=goal["id"], action="/tally", values={"current_number": 1})
        await op(provider, op="action_result", id=goal["id"], action="/tally", values={"final_count": 2}, result=True)
        result = (await until(lambda: sent(client, "action_result"), "the result at the client"))[0]
        assert result["values"] == {"final_count": 2}
        assert result["status"] == 4
        assert result["id"] == "t"

    run(check())


def test_the_labs_actions_and_answers_to_no_goal_are_refused():
    async def check() -> None:
        session = await connect(parts(replay=True))
        refused = await op(session, op="advertise_action", action="/count", type="hri_lab/Count")
        assert refused[0]["msg"] == "advertise_action: action /count is the lab's"
        stray = await op(session, op="action_result", id="g9", action="/tally", values={}, result=True)
        assert stray[0]["msg"].startswith("action_result: ")

    run(check())


def test_finish_takes_the_clients_actions_away():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        await op(session, op="advertise_action", action="/tally", type="hri_lab/Count")
        session.capability(AdvertiseAction).finish()
        assert lab.bridge.actions.get("/tally") is None
        assert not lab.bridge.actions.nodes.providers

    run(check())
