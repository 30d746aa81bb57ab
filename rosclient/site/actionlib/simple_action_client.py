"""actionlib's SimpleActionClient: one goal at a time over an ActionClient (a new goal stops tracking
the one before), its state as actionlib_msgs/GoalStatus (RECALLING shown as PENDING, PREEMPTING as
ACTIVE, as actionlib shows them), done/active/feedback callbacks."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import rospy
from actionlib.action_client import ActionClient, ClientGoalHandle, CommState, wait_until_done
from actionlib_msgs.msg import GoalStatus


class SimpleGoalState:
    PENDING, ACTIVE, DONE = 0, 1, 2


class SimpleActionClient:
    def __init__(self, ns: str, ActionSpec: Any) -> None:
        self.action_client = ActionClient(ns, ActionSpec)
        self.name = self.action_client.ns
        self.gh: ClientGoalHandle | None = None
        self.simple_state = SimpleGoalState.DONE
        self.done_cb: Callable[[int, Any], Any] | None = None
        self.active_cb: Callable[[], Any] | None = None
        self.feedback_cb: Callable[[Any], Any] | None = None

    def wait_for_server(self, timeout: Any = rospy.Duration()) -> bool:
        return self.action_client.wait_for_server(timeout)

    def send_goal(
        self,
        goal: Any,
        done_cb: Callable[[int, Any], Any] | None = None,
        active_cb: Callable[[], Any] | None = None,
        feedback_cb: Callable[[Any], Any] | None = None,
    ) -> None:
        self.stop_tracking_goal()
        self.done_cb, self.active_cb, self.feedback_cb = done_cb, active_cb, feedback_cb
        self.simple_state = SimpleGoalState.PENDING
        self.gh = self.action_client.send_goal(goal, self._handle_transition, self._handle_feedback)
        self._handle_transition(self.gh)  # a state it reached while being sent

    def send_goal_and_wait(
        self, goal: Any, execute_timeout: Any = rospy.Duration(), preempt_timeout: Any = rospy.Duration()
    ) -> int:
        self.send_goal(goal)
        if not self.wait_for_result(execute_timeout):
            rospy.logdebug("Canceling goal")
            self.cancel_goal()
            if self.wait_for_result(preempt_timeout):
                rospy.logdebug("Preempt finished within specified preempt_timeout [%.2f]", preempt_timeout.to_sec())
            else:
                rospy.logdebug("Preempt didn't finish specified preempt_timeout [%.2f]", preempt_timeout.to_sec())
        return self.get_state()

    def wait_for_result(self, timeout: Any = rospy.Duration()) -> bool:
        if self.gh is None:
            rospy.logerr("Called wait_for_result when no goal exists")
            return False
        return wait_until_done(self.gh, timeout)

    def get_result(self) -> Any:
        if self.gh is None:
            rospy.logerr("Called get_result when no goal is running")
            return None
        return self.gh.get_result()

    def get_state(self) -> int:
        if self.gh is None:
            rospy.logerr("Called get_state when no goal is running")
            return GoalStatus.LOST
        status = self.gh.get_goal_status()
        if status == GoalStatus.RECALLING:
            return GoalStatus.PENDING
        if status == GoalStatus.PREEMPTING:
            return GoalStatus.ACTIVE
        return status

    def get_goal_status_text(self) -> str:
        if self.gh is None:
            rospy.logerr("Called get_goal_status_text when no goal is running")
            return "ERROR: Called get_goal_status_text when no goal is running"
        return self.gh.get_goal_status_text()

    def cancel_goal(self) -> None:
        if self.gh is not None:
            self.gh.cancel()

    def cancel_all_goals(self) -> None:
        self.action_client.cancel_all_goals()

    def cancel_goals_at_and_before_time(self, time: Any) -> None:
        self.action_client.cancel_goals_at_and_before_time(time)

    def stop_tracking_goal(self) -> None:
        self.gh = None

    # --- the handle's callbacks -------------------------------------------------------------------
    def _handle_transition(self, gh: ClientGoalHandle) -> None:
        if gh is not self.gh:
            return  # a goal no longer tracked
        comm = gh.get_comm_state()
        if comm in (CommState.ACTIVE, CommState.PREEMPTING, CommState.WAITING_FOR_RESULT, CommState.DONE):
            if self.simple_state == SimpleGoalState.PENDING:
                self.simple_state = SimpleGoalState.ACTIVE
                if self.active_cb is not None:
                    self.active_cb()
        if comm == CommState.DONE and self.simple_state != SimpleGoalState.DONE:
            self.simple_state = SimpleGoalState.DONE
            if self.done_cb is not None:
                self.done_cb(gh.get_goal_status(), gh.get_result())

    def _handle_feedback(self, gh: ClientGoalHandle, feedback: Any) -> None:
        if gh is self.gh and self.feedback_cb is not None:
            self.feedback_cb(feedback)
