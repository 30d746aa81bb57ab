"""actionlib's ActionClient and ClientGoalHandle. A goal goes through the lab's action ops
(app/rosclient/actions.py), so it reaches the lab's own actions and every program's server alike;
the handle follows the goal's communication state as actionlib's does (WAITING_FOR_GOAL_ACK,
ACTIVE, WAITING_FOR_RESULT, DONE), calling `transition_cb(handle)` on each change and
`feedback_cb(handle, feedback)` on each feedback, on the connection's thread."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import rospy
from actionlib_msgs.msg import GoalStatus
from app.rosclient import actions, process

# action_msgs/GoalStatus (the ops') -> actionlib_msgs/GoalStatus
FROM_ROS2 = {
    actions.STATUS_SUCCEEDED: GoalStatus.SUCCEEDED,
    actions.STATUS_CANCELED: GoalStatus.PREEMPTED,
    actions.STATUS_ABORTED: GoalStatus.ABORTED,
    actions.STATUS_ACCEPTED: GoalStatus.PENDING,
    actions.STATUS_EXECUTING: GoalStatus.ACTIVE,
    actions.STATUS_CANCELING: GoalStatus.PREEMPTING,
}


class CommState:
    WAITING_FOR_GOAL_ACK = 0
    PENDING = 1
    ACTIVE = 2
    WAITING_FOR_RESULT = 3
    WAITING_FOR_CANCEL_ACK = 4
    RECALLING = 5
    PREEMPTING = 6
    DONE = 7
    LOST = 8


def get_name_of_constant(C: type, n: int) -> str:
    for name, value in vars(C).items():
        if value == n and not name.startswith("_"):
            return name
    return f"NO_SUCH_STATE_{n}"


def seconds(timeout: Any) -> float | None:
    """actionlib's timeouts: a rospy.Duration (zero: forever) or seconds."""
    value = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
    return None if value <= 0 else value


class ClientGoalHandle:
    def __init__(
        self,
        client: ActionClient,
        goal: Any,
        transition_cb: Callable[[ClientGoalHandle], Any] | None,
        feedback_cb: Callable[[ClientGoalHandle, Any], Any] | None,
    ) -> None:
        self.client, self.goal = client, goal
        self.transition_cb, self.feedback_cb = transition_cb, feedback_cb
        self.comm_state = CommState.WAITING_FOR_GOAL_ACK
        self.done = threading.Event()
        self.call = actions.GoalCall(client.ns, client.action_class, goal, self._feedback, self._result)
        self._transition(CommState.ACTIVE)  # the lab took the goal to its server

    def _transition(self, state: int) -> None:
        if state != self.comm_state:
            self.comm_state = state
            if self.transition_cb is not None:
                self.transition_cb(self)

    def _feedback(self, feedback: Any) -> None:
        if self.feedback_cb is not None:
            self.feedback_cb(self, feedback)

    def _result(self, call: actions.GoalCall) -> None:
        self._transition(CommState.WAITING_FOR_RESULT)
        self.done.set()
        self._transition(CommState.DONE)

    def get_comm_state(self) -> int:
        return self.comm_state

    def get_goal_status(self) -> int:
        return FROM_ROS2.get(self.call.status, GoalStatus.LOST)

    def get_goal_status_text(self) -> str:
        return self.call.error

    def get_terminal_state(self) -> int:
        if self.comm_state != CommState.DONE:
            rospy.logwarn("Asking for the terminal state when we're in [%s]", get_name_of_constant(CommState, self.comm_state))
        return self.get_goal_status()

    def get_result(self) -> Any:
        return self.call.result if self.done.is_set() else None

    def cancel(self) -> None:
        if not self.done.is_set():
            self.call.cancel()
            self._transition(CommState.WAITING_FOR_CANCEL_ACK)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ClientGoalHandle) and other.call is self.call

    def __hash__(self) -> int:
        return id(self.call)


class ActionClient:
    def __init__(self, ns: str, ActionSpec: Any) -> None:
        self.ns = rospy.resolve_name(ns)
        self.action_class = ActionSpec
        self.handles: list[ClientGoalHandle] = []

    def wait_for_server(self, timeout: Any = rospy.Duration()) -> bool:
        return process.wait_until(lambda: actions.server_ready(self.ns), seconds(timeout))

    def wait_for_action_server_to_start(self, timeout: Any = rospy.Duration()) -> bool:
        return self.wait_for_server(timeout)

    def send_goal(
        self,
        goal: Any,
        transition_cb: Callable[[ClientGoalHandle], Any] | None = None,
        feedback_cb: Callable[[ClientGoalHandle, Any], Any] | None = None,
    ) -> ClientGoalHandle:
        handle = ClientGoalHandle(self, goal, transition_cb, feedback_cb)
        self.handles.append(handle)
        return handle

    def cancel_all_goals(self) -> None:
        for handle in self.handles:
            handle.cancel()

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        self.cancel_all_goals()
