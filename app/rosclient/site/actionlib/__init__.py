"""actionlib (ROS 1): SimpleActionServer and SimpleActionClient over rosbridge's action ops
(app/rosclient/actions.py). The server's execute callback runs on a thread of its own per goal;
the client's callbacks run on the connection's thread, as actionlib runs them on its own."""
from __future__ import annotations

import threading
import traceback
from typing import Any, Callable

import rospy
from app.rosclient import actions, process

__all__ = ["SimpleActionServer", "SimpleActionClient", "GoalStatus", "SimpleGoalState"]


class GoalStatus:
    """actionlib_msgs/GoalStatus's states (what get_state() returns)."""
    PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED = 0, 1, 2, 3, 4, 5
    PREEMPTING, RECALLING, RECALLED, LOST = 6, 7, 8, 9


class SimpleGoalState:
    PENDING, ACTIVE, DONE = 0, 1, 2


_FROM_ROS2 = {actions.STATUS_SUCCEEDED: GoalStatus.SUCCEEDED, actions.STATUS_CANCELED: GoalStatus.PREEMPTED,
              actions.STATUS_ABORTED: GoalStatus.ABORTED, actions.STATUS_ACCEPTED: GoalStatus.PENDING,
              actions.STATUS_EXECUTING: GoalStatus.ACTIVE, actions.STATUS_CANCELING: GoalStatus.PREEMPTING}


def _seconds(timeout: Any) -> float | None:
    """actionlib's timeouts: a rospy.Duration (zero: forever) or seconds."""
    value = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
    return None if value <= 0 else value


class SimpleActionServer:
    def __init__(self, name: str, ActionSpec: Any, execute_cb: Callable | None = None, auto_start: bool = True) -> None:
        self.name = rospy.resolve_name(name)
        self.action_class, self.execute_callback = ActionSpec, execute_cb
        self._local = threading.local()
        self._serving: actions.ActionServing | None = None
        self._current: actions.ServedGoal | None = None
        self._lock = threading.Lock()
        if auto_start:
            self.start()

    def start(self) -> None:
        if self._serving is None:
            self._serving = actions.ActionServing(self.name, self.action_class, self._on_goal, self._on_cancel)

    def _on_goal(self, goal: actions.ServedGoal) -> None:
        with self._lock:
            previous, self._current = self._current, goal
        if previous is not None and not previous.finished:
            previous.cancel_requested.set()  # a new goal preempts the running one, as in actionlib
        threading.Thread(target=self._run, args=(goal,), daemon=True, name=f"actionlib{self.name}").start()

    def _run(self, goal: actions.ServedGoal) -> None:
        self._local.goal = goal
        try:
            if self.execute_callback is not None:
                self.execute_callback(goal.request)
            if not goal.finished:
                rospy.logwarn("Your executeCallback did not set the goal to a terminal status.  This is a bug in "
                              "your ActionServer implementation. Fix your code!  For now, the ActionServer will set "
                              "this goal to aborted")
                goal.finish(actions.STATUS_ABORTED, None)
        except Exception as exc:  # noqa: BLE001 - actionlib logs and aborts the goal
            rospy.logerr("Exception in your execute callback: %s\n%s", exc, traceback.format_exc())
            goal.finish(actions.STATUS_ABORTED, None)

    def _on_cancel(self, goal: actions.ServedGoal) -> None:
        goal.cancel_requested.set()

    def _goal(self) -> actions.ServedGoal:
        goal = getattr(self._local, "goal", None) or self._current
        if goal is None:
            raise rospy.ROSException("no goal is active")
        return goal

    def is_preempt_requested(self) -> bool:
        goal = getattr(self._local, "goal", None) or self._current
        return goal is not None and goal.cancel_requested.is_set()

    def is_active(self) -> bool:
        goal = getattr(self._local, "goal", None) or self._current
        return goal is not None and not goal.finished

    def is_new_goal_available(self) -> bool:
        goal = getattr(self._local, "goal", None)
        return goal is not None and self._current is not goal

    def publish_feedback(self, feedback: Any) -> None:
        self._goal().publish_feedback(feedback)

    def set_succeeded(self, result: Any = None, text: str = "") -> None:
        self._goal().finish(actions.STATUS_SUCCEEDED, result)

    def set_preempted(self, result: Any = None, text: str = "") -> None:
        self._goal().finish(actions.STATUS_CANCELED, result)

    def set_aborted(self, result: Any = None, text: str = "") -> None:
        self._goal().finish(actions.STATUS_ABORTED, result)


class SimpleActionClient:
    def __init__(self, ns: str, ActionSpec: Any) -> None:
        self.name = rospy.resolve_name(ns)
        self.action_class = ActionSpec
        self._call: actions.GoalCall | None = None
        self._text = ""

    def wait_for_server(self, timeout: Any = rospy.Duration()) -> bool:
        return process.wait_until(lambda: actions.server_ready(self.name), _seconds(timeout))

    def send_goal(self, goal: Any, done_cb: Callable | None = None, active_cb: Callable | None = None,
                  feedback_cb: Callable | None = None) -> None:
        if self._call is not None and not self._call.done.is_set():
            self._call.on_result = None
        def finished(call: actions.GoalCall) -> None:
            if done_cb is not None:
                done_cb(_FROM_ROS2.get(call.status, GoalStatus.LOST), call.result)

        self._call = actions.GoalCall(self.name, self.action_class, goal, feedback_cb, finished)
        if active_cb is not None:
            active_cb()

    def send_goal_and_wait(self, goal: Any, execute_timeout: Any = rospy.Duration(),
                           preempt_timeout: Any = rospy.Duration()) -> int:
        self.send_goal(goal)
        if not self.wait_for_result(execute_timeout):
            self.cancel_goal()
            self.wait_for_result(preempt_timeout)
        return self.get_state()

    def wait_for_result(self, timeout: Any = rospy.Duration()) -> bool:
        if self._call is None:
            rospy.logerr("Called wait_for_result when no goal exists")
            return False
        return self._call.done.wait(_seconds(timeout))

    def get_result(self) -> Any:
        return None if self._call is None or not self._call.done.is_set() else self._call.result

    def get_state(self) -> int:
        if self._call is None:
            return GoalStatus.LOST
        return _FROM_ROS2.get(self._call.status, GoalStatus.LOST)

    def get_goal_status_text(self) -> str:
        return "" if self._call is None else self._call.error

    def cancel_goal(self) -> None:
        if self._call is not None:
            self._call.cancel()

    def cancel_all_goals(self) -> None:
        self.cancel_goal()

    def stop_tracking_goal(self) -> None:
        self._call = None
