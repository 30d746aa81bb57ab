"""send_action_goal / cancel_action_goal (app/rosbridge/capabilities/actions.py): a goal on the lab's
ActionServer, its feedback when asked, its result with action_msgs/GoalStatus codes; the goals of
a client that goes stop."""

from app.ros.actions import TERMINAL, GoalStatus
from app.rosbridge.capabilities.actions import Actions
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_a_goal_ends_with_its_result_and_status_code():
    async def check() -> None:
        session = await connect(parts(replay=True))
        result = await op(session, op="send_action_goal", id="g", action="/count", args={"count": 0}, feedback=True)
        assert result == [
            {
                "op": "action_result",
                "id": "g",
                "action": "/count",
                "values": {"final_count": 0},
                "status": 4,
                "result": True,
            }
        ]

    run(check())


def test_an_unknown_action_or_a_bad_goal_is_an_aborted_result_and_a_status():
    async def check() -> None:
        session = await connect(parts(replay=True))
        unknown = await op(session, op="send_action_goal", id="u", action="/fly", args={})
        assert unknown[0]["op"] == "action_result"
        assert unknown[0]["status"] == 6
        assert not unknown[0]["result"]
        assert unknown[1]["msg"] == "send_action_goal: action /fly does not exist"
        bad = await op(session, op="send_action_goal", id="b", action="/count", args={"count": -1})
        assert bad[0]["status"] == 6
        assert "count" in bad[1]["msg"]
        refused = await op(session, op="cancel_action_goal", id="nothing")
        assert refused[0]["msg"] == 'cancel_action_goal: no goal with id "nothing" from this client'

    run(check())


def test_cancel_preempts_the_goal_and_finish_stops_the_ones_still_running():
    async def check() -> None:
        session = await connect(parts(replay=True))
        await session.handle('{"op": "send_action_goal", "id": "long", "action": "/count", "args": {"count": 3600}}')
        await session.handle('{"op": "send_action_goal", "id": "other", "action": "/count", "args": {"count": 3600}}')
        goals = session.capability(Actions).goals
        assert set(goals) == {"long", "other"}
        assert goals["other"].status == GoalStatus.REJECTED  # one /count at a time
        await session.handle('{"op": "cancel_action_goal", "id": "long"}')
        await until(lambda: goals["long"].status in TERMINAL, "the canceled goal's end")
        result = await until(lambda: [m for m in sent(session, "action_result") if m["id"] == "long"], "its result")
        assert result[0]["status"] == 5  # canceled
        await session.handle('{"op": "send_action_goal", "id": "again", "action": "/count", "args": {"count": 3600}}')
        running = goals["again"]
        await until(lambda: running.status == GoalStatus.ACTIVE, "the goal running")
        session.capability(Actions).finish()
        await until(lambda: running.status in TERMINAL, "the goal stopped with its client")
        assert running.status == GoalStatus.PREEMPTED
        await session.close()

    run(check())
