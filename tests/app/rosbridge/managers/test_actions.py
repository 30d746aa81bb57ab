"""Actions (app/rosbridge/managers/actions.py): the lab's ActionServer a client sends goals to, and
the actions nodes provide in it, which go with their client."""

import pytest

from app.ros.actions import TERMINAL, GoalStatus
from app.ros.messages import message_from_args
from tests.app.rosbridge.clients import connect, parts, run
from tests.waiting import wait_for


def test_the_labs_actions_take_goals_and_a_cancelled_goal_is_preempted():
    actions = parts(replay=True).bridge.actions
    assert "/count" in actions.names()
    count = actions.get("/count")
    assert count is not None and actions.get("/nothing") is None
    handle = actions.send_goal(count, message_from_args(count.goal, {"count": 1000}, "goal"))
    actions.cancel(handle)
    wait_for(lambda: handle.status in TERMINAL)
    assert handle.status == GoalStatus.PREEMPTED


def test_a_nodes_action_is_listed_while_its_client_is_there():
    async def check() -> None:
        lab = parts(replay=True)
        provider = await connect(lab)
        actions = lab.bridge.actions
        actions.advertise("/tally", "hri_lab/Count", provider)
        assert "/tally" in actions.names() and actions.get("/tally") is not None
        with pytest.raises(ValueError, match="/count is the lab's"):
            actions.advertise("/count", "hri_lab/Count", provider)
        other = await connect(lab)
        assert not actions.unadvertise("/tally", other)  # not its
        actions.drop(provider)
        assert "/tally" not in actions.names()

    run(check())
