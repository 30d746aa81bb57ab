"""actionlib's SimpleActionClient: one goal at a time (a new goal stops tracking the one before),
its state as actionlib_msgs/GoalStatus, done/active/feedback callbacks (on the connection's thread)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import rospy
from actionlib.action_client import FROM_ROS2, seconds
from actionlib_msgs.msg import GoalStatus
from app.rosclient import actions, process


class SimpleGoalState:
    PENDING, ACTIVE, DONE = 0, 1, 2


class SimpleActionClient:
    def __init__(self, ns: str, ActionSpec: Any) -> None:
        self.name = rospy.resolve_name(ns)
        self.action_class = ActionSpec
        self._call: actions.GoalCall | None = None

    def wait_for_server(self, timeout: Any = rospy.Duration()) -> bool:
        return process.wait_until(lambda: actions.server_ready(self.name), seconds(timeout))

    def send_goal(
        self,
        goal: Any,
        done_cb: Callable[[int, Any], Any] | None = None,
        active_cb: Callable[[], Any] | None = None,
        feedback_cb: Callable[[Any], Any] | None = None,
    ) -> None:
        if self._call is not None and not self._call.done.is_set():
            self._call.on_result = None  # no longer tracked: its end calls nothing

        def finished(call: actions.GoalCall) -> None:
            if done_cb is not None:
                done_cb(FROM_ROS2.get(call.status, GoalStatus.LOST), call.result)

        self._call = actions.GoalCall(self.name, self.action_class, goal, feedback_cb, finished)
        if active_cb is not None:
            active_cb()

    def send_goal_and_wait(
        self, goal: Any, execute_timeout: Any = rospy.Duration(), preempt_timeout: Any = rospy.Duration()
    ) -> int:
        self.send_goal(goal)
        if not self.wait_for_result(execute_timeout):
            rospy.logdebug("Canceling goal")
            self.cancel_goal()
            self.wait_for_result(preempt_timeout)
        return self.get_state()

    def wait_for_result(self, timeout: Any = rospy.Duration()) -> bool:
        if self._call is None:
            rospy.logerr("Called wait_for_result when no goal exists")
            return False
        return self._call.done.wait(seconds(timeout))

    def get_result(self) -> Any:
        return None if self._call is None or not self._call.done.is_set() else self._call.result

    def get_state(self) -> int:
        if self._call is None:
            rospy.logerr("Called get_state when no goal is running")
            return GoalStatus.LOST
        return FROM_ROS2.get(self._call.status, GoalStatus.LOST)

    def get_goal_status_text(self) -> str:
        if self._call is None:
            rospy.logerr("Called get_goal_status_text when no goal is running")
            return "ERROR: Called get_goal_status_text when no goal is running"
        return self._call.error

    def simple_state(self) -> int:
        if self._call is None or self._call.done.is_set():
            return SimpleGoalState.DONE
        return SimpleGoalState.ACTIVE if self._call.status == actions.STATUS_EXECUTING else SimpleGoalState.PENDING

    def cancel_goal(self) -> None:
        if self._call is not None:
            self._call.cancel()

    def cancel_all_goals(self) -> None:
        self.cancel_goal()

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        self.cancel_goal()

    def stop_tracking_goal(self) -> None:
        self._call = None
