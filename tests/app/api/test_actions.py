"""Actions over HTTP (goal / feedback / result / cancel, actionlib states), teleop and /robot."""

import numpy as np
import pytest

from sim.robot.panda import SIDE_Q

from tests.waiting import wait_for, wait_terminal


def test_action_list_and_definitions(client):
    assert {a["name"] for a in client.get("/actions").json()} == {
        "/count",
        "/move_to_start",
        "/run_experiment",
        "/compare_controllers",
    }
    assert (
        client.get("/actions/count").json()["definition"]
        == "int32 count\n---\nint32 final_count\n---\nint32 current_number"
    )
    assert client.get("/actions/nope").status_code == 404


def test_count_three_succeeds_with_three_feedbacks(client):
    goal = client.post("/actions/count/goals", json={"count": 3})
    assert goal.status_code == 202
    goal_id = goal.json()["goal_id"]
    assert goal.json()["status"] in ("pending", "active")
    view = wait_terminal(client, "count", goal_id)
    assert view["status"] == "succeeded"
    assert view["feedback"] == [{"current_number": 1}, {"current_number": 2}, {"current_number": 3}]
    assert view["result"] == {"final_count": 3}


def test_cancel_mid_way_ends_preempted_and_a_busy_server_rejects(client):
    goal_id = client.post("/actions/count/goals", json={"count": 10}).json()["goal_id"]
    # long-poll until the first number
    first = client.get(f"/actions/count/goals/{goal_id}", params={"after": 0, "wait": 5}).json()
    assert first["feedback"][0] == {"current_number": 1}
    # a second goal while one is active is rejected (documented: one goal at a time)
    second = client.post("/actions/count/goals", json={"count": 1})
    assert second.status_code == 409
    assert second.json()["status"] == "rejected"
    assert goal_id in second.json()["message"]
    canceled = client.post(f"/actions/count/goals/{goal_id}/cancel").json()
    assert canceled["status"] in ("preempting", "preempted")
    counted_at_cancel = canceled["feedback_count"]
    view = wait_terminal(client, "count", goal_id)
    assert view["status"] == "preempted"
    # it stopped at once: the result is the last number it fed back, the one it had reached
    assert view["result"]["final_count"] == view["feedback"][-1]["current_number"] == view["feedback_count"]
    assert view["feedback_count"] == counted_at_cancel
    # free again
    third = client.post("/actions/count/goals", json={"count": 0}).json()
    assert wait_terminal(client, "count", third["goal_id"])["status"] == "succeeded"


def test_goal_validation_and_unknown_goals(client):
    assert client.post("/actions/count/goals", json={"count": -1}).status_code == 422
    assert client.post("/actions/count/goals", json={"count": "3"}).status_code == 422
    assert client.get("/actions/count/goals/deadbeef").status_code == 404
    assert client.post("/actions/count/goals/deadbeef/cancel").status_code == 404
    assert client.post("/actions/run_experiment/goals", json={"participant": "sleepy"}).status_code == 422


def test_feedback_stream(client):
    goal_id = client.post("/actions/count/goals", json={"count": 2}).json()["goal_id"]
    messages = []
    with client.websocket_connect(f"/actions/count/goals/{goal_id}/stream") as ws:
        while True:
            msg = ws.receive_json()
            messages.append(msg)
            if "status" in msg:
                break
    assert messages == [
        {"feedback": {"current_number": 1}},
        {"feedback": {"current_number": 2}},
        {"status": "succeeded", "result": {"final_count": 2}, "message": "done"},
    ]


def test_a_goal_that_ends_while_the_stream_sends_its_feedback_ends_with_its_result(client, monkeypatch):
    """The stream's last message is the goal's end as it is: here the goal succeeds just after the
    stream took the snapshot holding its last feedback (what a loaded machine's threads can do)."""
    from app.ros.actions import GoalHandle, GoalStatus

    goal_id = client.post("/actions/count/goals", json={"count": 50}).json()["goal_id"]
    handle = client.app.state.actions.goal("count", goal_id)
    wait_for(lambda: handle.view()["feedback_count"] >= 1)
    taken = GoalHandle.view

    def snapshot_then_the_goal_ends(self, after=0):
        view = taken(self, after)
        if self is handle and view["feedback"]:
            self.set_status(GoalStatus.SUCCEEDED, "ended meanwhile", {"final_count": 7})
        return view

    monkeypatch.setattr(GoalHandle, "view", snapshot_then_the_goal_ends)
    with client.websocket_connect(f"/actions/count/goals/{goal_id}/stream") as ws:
        messages = [ws.receive_json()]
        while "status" not in messages[-1]:
            messages.append(ws.receive_json())
    assert messages[-1] == {"status": "succeeded", "result": {"final_count": 7}, "message": "ended meanwhile"}


def test_move_to_start_from_a_jogged_pose(client, lab):
    client.post("/services/stop_cooperative_lifting")
    client.post("/services/reset_simulation")
    # jog away with the teleop keys (w: +x), then drive back with the action
    assert client.post("/teleop/key", json={"key": "w"}).json()["successful"] is True
    wait_for(lambda: not np.allclose(lab.snapshot().q, SIDE_Q, atol=1e-3))  # moving or moved (jogging brakes first)
    goal_id = client.post("/actions/move_to_start/goals").json()["goal_id"]
    view = wait_terminal(client, "move_to_start", goal_id)
    assert view["status"] == "succeeded", view
    assert view["feedback"][-1]["progress"] == pytest.approx(1.0)
    assert lab.snapshot().q == pytest.approx(SIDE_Q, abs=2e-3)
    assert lab.snapshot().error is None


def test_teleop_refusals(client):
    assert client.post("/teleop/key", json={"key": "x"}).status_code == 422
    client.post("/services/start_cooperative_lifting", json={"force": 10.0})
    refused = client.post("/teleop/key", json={"key": "w"})
    assert refused.status_code == 409
    assert "lifting" in refused.json()["reason"]
    client.post("/services/stop_cooperative_lifting")


def test_move_to_start_is_refused_up_front_while_lifting_or_in_error(client, lab):
    client.post("/services/start_cooperative_lifting", json={"force": 10.0})
    response = client.post("/actions/move_to_start/goals")
    assert response.status_code == 409
    view = response.json()
    assert view["status"] == "rejected"
    assert view["message"] == "cooperative lifting is running: call /stop_cooperative_lifting first"
    assert "Error" not in view["message"]  # no exception name leaks
    client.post("/services/stop_cooperative_lifting")
    from tests.app.api.test_services import _too_fast

    lab.call(_too_fast)
    response = client.post("/actions/move_to_start/goals")
    assert response.status_code == 409
    assert response.json()["message"].startswith("the robot is in error (cartesian velocity limit")
    assert "call /error_recovery first" in response.json()["message"]
    client.post("/services/error_recovery")


def test_a_goal_failure_aborts_with_its_message_only(client):
    from app.ros.actions import Action, ActionServer, GoalFailure
    from app.ros.messages import Empty

    def fail(lab, goal, handle):
        raise GoalFailure("robot reflex: joint 4 position limit")

    def bug(lab, goal, handle):
        raise KeyError("x")

    server = ActionServer(
        [Action("/fail", "t/Fail", Empty, Empty, Empty, fail), Action("/bug", "t/Bug", Empty, Empty, Empty, bug)], None
    )
    failed, buggy = server.send_goal(server.get("fail"), Empty()), server.send_goal(server.get("bug"), Empty())
    failed.wait_for_update(0, 5.0)
    buggy.wait_for_update(0, 5.0)
    assert (failed.status.value, failed.message) == ("aborted", "robot reflex: joint 4 position limit")
    assert (buggy.status.value, buggy.message) == ("aborted", "KeyError: 'x'")  # a handler bug says what it is


def test_compare_controllers_refusals(client):
    for goal, field in (
        ({"controllers": "sp,pid"}, "controllers"),
        ({"trials": 0}, "trials"),
        ({"participants": "calm,sleepy"}, "participants"),
    ):
        refused = client.post("/actions/compare_controllers/goals", json=goal)
        assert refused.status_code == 422
        assert refused.json()["detail"][0]["loc"][-1] == field


def test_experiment_goals_refuse_a_bad_set_with_the_parameter_servers_message(client):
    for action in ("run_experiment", "compare_controllers"):
        for text, message in (
            ("alpha=3", "Parameter {alpha} doesn't comply with floating point range."),
            ("k_t=fast", "Wrong parameter type, parameter {k_t} is of type {double}"),
            ("f_n_min=5", "parameter 'f_n_min' does not apply to a headless experiment"),
        ):
            refused = client.post(f"/actions/{action}/goals", json={"set": text})
            assert refused.status_code == 409, refused.text
            assert refused.json()["status"] == "rejected"
            assert message in refused.json()["message"]
        malformed = client.post(f"/actions/{action}/goals", json={"set": "alpha 0.5"})  # not NAME=VALUE: the schema's
        assert malformed.status_code == 422
        assert malformed.json()["detail"][0]["loc"][-1] == "set"
    assert "string set" in client.get("/actions/run_experiment").json()["definition"]


def test_robot_model(client):
    robot = client.get("/robot").json()
    assert robot["root_link"] == "panda_link0"
    joints = {j["name"]: j for j in robot["joints"]}
    assert joints["panda_joint4"]["upper"] == pytest.approx(-0.0698)
    assert joints["panda_joint1"]["velocity"] == pytest.approx(2.175)
    assert joints["panda_joint1"]["parent"] == "panda_link0"
    assert joints["panda_joint1"]["child"] == "panda_link1"
    assert "panda_link8" in robot["links"]
