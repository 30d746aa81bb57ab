"""app/ros/node_actions.py: an action a node provides runs its goals through the lab's ActionServer
with actionlib's states: the goal sent to the node, its feedback and result (4 succeeded, 5
canceled, 6 aborted, `result: false` aborted), a cancel sent to it once, its goals aborted when it
withdraws, and its feedback and results checked against the type's models when the lab knows it."""

from __future__ import annotations

import asyncio
from concurrent.futures import Future

import pytest

from app.ros.actions import TERMINAL, Action, ActionServer, GoalStatus
from app.ros.messages import Int64, RosMessage
from app.ros.node_actions import ABORTED, CANCELED, SUCCEEDED, NodeActions
from app.ros.node_services import OpenMessage
from tests.app.ros.nodes import Node, event_loop
from tests.waiting import wait_for


class Order(RosMessage):
    order: Int64


class Sequence(RosMessage):
    sequence: list[int]


class Partial(RosMessage):
    partial: list[int]


def lab_fib(lab, goal, handle):
    return Sequence(sequence=[0])


LAB_ACTION = Action("/lab_fibonacci", "hri_lab/Fibonacci", Order, Sequence, Partial, lab_fib, "the lab's")


@pytest.fixture
def loop():
    with event_loop() as running:
        yield running


@pytest.fixture
def actions():
    return NodeActions(ActionServer([LAB_ACTION], lab=None))


def goal_at(node: Node, actions: NodeActions, name: str, goal: dict):
    """A goal sent through the lab's server, and the send_action_goal its node got."""
    handle = actions.server.send_goal(actions.server.get(name), actions.server.get(name).goal.model_validate(goal))
    return handle, node.next("send_action_goal")


def finished(handle) -> dict:
    handle.wait_for_update(after=10**9, timeout=30.0)  # returns on a terminal state
    assert handle.status in TERMINAL
    return handle.view()


def test_a_goal_goes_to_its_node_and_ends_with_the_nodes_feedback_and_result(actions, loop):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "my_pkg/action/Fibonacci", node)  # unknown to the lab: JSON objects
    assert "provided by node /fib_server" in actions.server.get("/fibonacci").description
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 3})
    assert (sent["action"], sent["action_type"], sent["args"], sent["feedback"]) == (
        "/fibonacci",
        "my_pkg/action/Fibonacci",
        {"order": 3},
        True,
    )
    actions.feedback(node, sent["id"], "/fibonacci", {"partial": [0, 1]})
    actions.result(node, sent["id"], "/fibonacci", {"sequence": [0, 1, 1]}, SUCCEEDED, True)
    view = finished(handle)
    assert view["status"] == GoalStatus.SUCCEEDED.value
    assert view["feedback"] == [{"partial": [0, 1]}] and view["result"] == {"sequence": [0, 1, 1]}
    assert actions.pending == {}


@pytest.mark.parametrize(
    ("status", "ok", "values", "outcome", "message"),
    [
        (ABORTED, True, {}, GoalStatus.ABORTED, "aborted by node /fib_server"),
        (SUCCEEDED, False, "out of numbers", GoalStatus.ABORTED, "aborted by node /fib_server: out of numbers"),
        (CANCELED, True, {"sequence": [0]}, GoalStatus.PREEMPTED, "canceled by node /fib_server"),
        (2, True, {}, GoalStatus.ABORTED, "ended the goal with status 2"),
    ],
)
def test_the_nodes_status_decides_the_goals_end(actions, loop, status, ok, values, outcome, message):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 3})
    actions.result(node, sent["id"], "/fibonacci", values, status, ok)
    view = finished(handle)
    assert view["status"] == outcome.value and message in view["message"]


class CountedFuture(Future):
    """A goal's future that counts the goal thread's looks at it (each a wait of POLL_S)."""

    looks = 0

    def result(self, timeout=None):
        self.looks += 1
        return super().result(timeout)


def test_a_cancel_is_sent_to_the_node_once_and_the_goal_preempting_until_it_answers(actions, loop):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 30})
    counted = actions.pending[sent["id"]].result = CountedFuture()
    wait_for(lambda: counted.looks > 0)  # the goal thread waits on it
    actions.server.cancel(handle)
    cancel = node.next("cancel_action_goal")
    assert (cancel["id"], cancel["action"]) == (sent["id"], "/fibonacci")
    assert handle.status == GoalStatus.PREEMPTING
    looks = counted.looks
    wait_for(lambda: counted.looks >= looks + 3)  # it looked again, and again, while the node took its time
    asyncio.run_coroutine_threadsafe(asyncio.sleep(0), loop).result(30)  # what it sent the node has arrived
    assert node.sent.empty()  # one cancel, however long the node takes
    actions.result(node, sent["id"], "/fibonacci", {"sequence": [0, 1]}, CANCELED, True)
    view = finished(handle)
    assert view["status"] == GoalStatus.PREEMPTED.value and view["result"] == {"sequence": [0, 1]}


def test_a_node_that_rejects_the_cancel_succeeds_its_goal(actions, loop):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 30})
    wait_for(lambda: handle.status == GoalStatus.ACTIVE)
    actions.server.cancel(handle)
    node.next("cancel_action_goal")
    actions.result(node, sent["id"], "/fibonacci", {"sequence": [0]}, SUCCEEDED, True)
    assert finished(handle)["status"] == GoalStatus.SUCCEEDED.value


def test_a_node_that_withdraws_takes_its_action_and_aborts_its_goals(actions, loop):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle, _ = goal_at(node, actions, "/fibonacci", {"order": 3})
    actions.drop(node)  # it disconnected
    view = finished(handle)
    assert view["status"] == GoalStatus.ABORTED.value
    assert "node /fib_server withdrew action /fibonacci before the goal ended" in view["message"]
    assert actions.server.get("/fibonacci") is None and actions.providers == {}


def test_an_action_is_one_nodes_and_the_labs_own_are_nobodys(actions, loop):
    first, second = Node("/first", loop), Node("/second", loop)
    with pytest.raises(ValueError, match="action /lab_fibonacci is the lab's"):
        actions.advertise("/lab_fibonacci", "hri_lab/Fibonacci", first)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", first)
    with pytest.raises(ValueError, match="already provided by node /first"):
        actions.advertise("/fibonacci", "my_pkg/Fibonacci", second)
    assert not actions.unadvertise("/fibonacci", second)
    assert actions.unadvertise("/fibonacci", first)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", second)
    assert actions.providers["/fibonacci"] is second


def test_a_known_types_feedback_and_result_are_checked_against_its_models(actions, loop):
    node = Node("/fib_server", loop)
    actions.advertise("/fibonacci", "hri_lab/action/Fibonacci", node)  # the lab's type: its models check
    assert actions.server.get("/fibonacci").feedback is Partial
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 3})
    with pytest.raises(ValueError, match="not a hri_lab/action/Fibonacci feedback"):
        actions.feedback(node, sent["id"], "/fibonacci", {"partial": "many"})
    actions.result(node, sent["id"], "/fibonacci", {"sequence": "many"}, SUCCEEDED, True)
    view = finished(handle)
    assert view["status"] == GoalStatus.ABORTED.value
    assert "the node's result is not a hri_lab/action/Fibonacci result" in view["message"]


def test_only_the_goals_node_answers_it(actions, loop):
    node, other = Node("/fib_server", loop), Node("/other", loop)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle, sent = goal_at(node, actions, "/fibonacci", {"order": 3})
    for session, goal_id, name in ((other, sent["id"], "/fibonacci"), (node, "nope", "/fibonacci"),
                                   (node, 12, "/fibonacci"), (node, sent["id"], "/other")):  # fmt: skip
        with pytest.raises(ValueError, match="waits for this client"):
            actions.result(session, goal_id, name, {}, SUCCEEDED, True)
    actions.result(node, sent["id"], "/fibonacci", {}, SUCCEEDED, True)
    assert finished(handle)["status"] == GoalStatus.SUCCEEDED.value


def test_a_node_not_connected_yet_aborts_the_goal_by_name(actions):
    node = Node("/early", loop=None)
    actions.advertise("/fibonacci", "my_pkg/Fibonacci", node)
    handle = actions.server.send_goal(actions.server.get("/fibonacci"), OpenMessage.model_validate({}))
    view = finished(handle)
    assert view["status"] == GoalStatus.ABORTED.value and "node /early is not connected" in view["message"]
