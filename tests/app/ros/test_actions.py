"""app/ros/actions.py: actionlib's goal states — succeeded, aborted (a failure or any exception),
preempted (a cancel, before or while it runs), rejected (busy, or a precondition) — feedback as it
comes, and the .action text. Goals run in threads: the tests wait on the goal's own condition."""

import pytest

from app.ros.actions import TERMINAL, Action, ActionServer, GoalFailure, GoalPreempted, GoalStatus
from app.ros.messages import Int64, RosMessage, String


class Count(RosMessage):
    count: Int64


class Done(RosMessage):
    reached: Int64


class Progress(RosMessage):
    at: Int64
    note: String = ""


def count(lab, goal: Count, handle) -> Done:
    for n in range(goal.count):
        handle.feedback(Progress(at=n))
        if goal.count > 5 and handle.wait(60.0):  # a long goal waits: a cancel wakes it
            return Done(reached=n)
    if goal.count < 0:
        raise GoalFailure("a count is >= 0")
    if goal.count == 4:
        raise ZeroDivisionError("4 is unlucky")
    if goal.count == 5:
        raise GoalPreempted(Done(reached=-1), "stopped by itself")
    return Done(reached=goal.count)


COUNT = Action(
    "/count",
    "hri_lab/Count",
    Count,
    Done,
    Progress,
    count,
    "counts",
    precondition=lambda lab, goal: "the lab is closed" if lab == "closed" and goal.count else None,
)


def finished(handle):
    handle.wait_for_update(after=10**9, timeout=30.0)  # returns on a terminal state
    assert handle.status in TERMINAL
    return handle.view()


def test_the_action_text_is_goal_result_feedback():
    assert COUNT.definition == "int64 count\n---\nint64 reached\n---\nint64 at\nstring note"


@pytest.mark.parametrize(
    ("n", "status", "message", "result"),
    [
        (3, "succeeded", "done", {"reached": 3}),
        (-1, "aborted", "a count is >= 0", None),
        (4, "aborted", "ZeroDivisionError: 4 is unlucky", None),
        (5, "preempted", "stopped by itself", {"reached": -1}),
    ],
)
def test_how_a_goal_ends(n, status, message, result):
    view = finished(ActionServer([COUNT], lab=None).send_goal(COUNT, Count(count=n)))
    assert (view["status"], view["message"], view["result"]) == (status, message, result)


def test_feedback_arrives_in_order_and_a_view_can_start_after_the_n_th():
    handle = ActionServer([COUNT], lab=None).send_goal(COUNT, Count(count=3))
    finished(handle)
    assert [f["at"] for f in handle.view()["feedback"]] == [0, 1, 2]
    assert handle.view(after=2)["feedback"] == [{"at": 2, "note": ""}]


def test_a_cancel_preempts_a_running_goal_and_a_second_goal_is_rejected_meanwhile():
    server = ActionServer([COUNT], lab=None)
    first = server.send_goal(COUNT, Count(count=10))
    first.wait_for_update(after=0, timeout=30.0)  # it runs: its first feedback came
    second = server.send_goal(COUNT, Count(count=1))
    assert second.status == GoalStatus.REJECTED
    assert first.id in second.message
    server.cancel(first)
    view = finished(first)
    assert (view["status"], view["message"], view["result"]) == ("preempted", "canceled", {"reached": 0})
    assert finished(server.send_goal(COUNT, Count(count=1)))["status"] == "succeeded"  # free again


def test_a_precondition_rejects_up_front():
    handle = ActionServer([COUNT], lab="closed").send_goal(COUNT, Count(count=2))
    assert (handle.status, handle.message) == (GoalStatus.REJECTED, "the lab is closed")


def test_actions_come_and_go_and_goals_are_found_by_their_action():
    server = ActionServer([COUNT], lab=None)
    with pytest.raises(ValueError, match="exists already"):
        server.add(COUNT)
    handle = server.send_goal(COUNT, Count(count=0))
    finished(handle)
    assert server.goal("count", handle.id) is handle
    assert server.goal("/other", handle.id) is None
    assert server.remove("count") is COUNT
    assert server.get("/count") is None


def test_old_finished_goals_are_forgotten(monkeypatch):
    monkeypatch.setattr(ActionServer, "keep_goals", 3)
    server = ActionServer([COUNT], lab=None)
    handles = []
    for _ in range(5):
        handles.append(server.send_goal(COUNT, Count(count=0)))
        finished(handles[-1])
    assert list(server.goals) == [h.id for h in handles[2:]]  # the newest three
