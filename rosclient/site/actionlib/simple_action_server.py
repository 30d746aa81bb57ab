"""actionlib's SimpleActionServer: one goal at a time over an ActionServer. A new goal preempts the
active one (is_preempt_requested() turns true) and waits as the next goal; a goal behind it that
another replaces is canceled. With an execute callback, each goal runs in it on the server's
execute thread; without, the program accepts goals itself (register_goal_callback, accept_new_goal)."""

from __future__ import annotations

import threading
import traceback
from collections.abc import Callable
from typing import Any

import rospy
from actionlib.action_server import ActionServer
from actionlib.server_goal_handle import ACTIVE, PREEMPTING, ServerGoalHandle

REPLACED = "This goal was canceled because another goal was received by the simple action server"
EXECUTE_WAIT_S = 0.1  # the execute thread's longest wait between looks at its state


class SimpleActionServer:
    def __init__(
        self, name: str, ActionSpec: Any, execute_cb: Callable[[Any], Any] | None = None, auto_start: bool = True
    ) -> None:
        self.new_goal = False
        self.preempt_request = False
        self.new_goal_preempt_request = False
        self.execute_callback = execute_cb
        self.goal_callback: Callable[[], Any] | None = None
        self.preempt_callback: Callable[[], Any] | None = None
        self.need_to_terminate = False
        self.lock = threading.RLock()
        self.execute_condition = threading.Condition(self.lock)
        self.current_goal = ServerGoalHandle()
        self.next_goal = ServerGoalHandle()
        if self.execute_callback is not None:
            self.execute_thread = threading.Thread(target=self.executeLoop, daemon=True, name="actionlib-execute")
            self.execute_thread.start()
        self.action_server = ActionServer(
            name, ActionSpec, self.internal_goal_callback, self.internal_preempt_callback, auto_start
        )

    def start(self) -> None:
        self.action_server.start()

    def accept_new_goal(self) -> Any:
        with self.lock:
            if not self.new_goal or self.next_goal.get_goal() is None:
                rospy.logerr("Attempting to accept the next goal when a new goal is not available")
                return None
            if self.is_active() and self.current_goal.get_goal() is not None and self.current_goal != self.next_goal:
                self.current_goal.set_canceled(None, REPLACED)
            self.current_goal, self.new_goal = self.next_goal, False
            self.preempt_request, self.new_goal_preempt_request = self.new_goal_preempt_request, False
            self.current_goal.set_accepted("This goal has been accepted by the simple action server")
            return self.current_goal.get_goal()

    def is_new_goal_available(self) -> bool:
        return self.new_goal

    def is_preempt_requested(self) -> bool:
        return self.preempt_request

    def is_active(self) -> bool:
        if self.current_goal.get_goal() is None:
            return False
        return self.current_goal.get_goal_status().status in (ACTIVE, PREEMPTING)

    def set_succeeded(self, result: Any = None, text: str = "") -> None:
        with self.lock:
            self.current_goal.set_succeeded(result, text)

    def set_aborted(self, result: Any = None, text: str = "") -> None:
        with self.lock:
            self.current_goal.set_aborted(result, text)

    def set_preempted(self, result: Any = None, text: str = "") -> None:
        with self.lock:
            self.current_goal.set_canceled(result, text)

    def publish_feedback(self, feedback: Any) -> None:
        self.current_goal.publish_feedback(feedback)

    def get_default_result(self) -> Any:
        return self.action_server.spec.Result()

    def register_goal_callback(self, cb: Callable[[], Any]) -> None:
        if self.execute_callback is not None:
            rospy.logwarn(
                "Cannot call SimpleActionServer.register_goal_callback() because an executeCallback exists. "
                "Not going to register it."
            )
        else:
            self.goal_callback = cb

    def register_preempt_callback(self, cb: Callable[[], Any]) -> None:
        self.preempt_callback = cb

    # --- the ActionServer's callbacks (its thread) ------------------------------------------------
    def internal_goal_callback(self, goal: ServerGoalHandle) -> None:
        with self.lock:
            stamp = goal.get_goal_id().stamp.to_nsec()
            newest_next = self.next_goal.get_goal() is None or stamp >= self.next_goal.get_goal_id().stamp.to_nsec()
            newest_current = (
                self.current_goal.get_goal() is None or stamp >= self.current_goal.get_goal_id().stamp.to_nsec()
            )
            if not (newest_next and newest_current):
                goal.set_canceled(None, REPLACED)
                return
            if self.next_goal.get_goal() is not None and (
                self.current_goal.get_goal() is None or self.next_goal != self.current_goal
            ):
                self.next_goal.set_canceled(None, REPLACED)
            self.next_goal, self.new_goal, self.new_goal_preempt_request = goal, True, False
            if self.is_active():
                self.preempt_request = True
                if self.preempt_callback is not None:
                    self.preempt_callback()
            if self.goal_callback is not None:
                self.goal_callback()
            self.execute_condition.notify()

    def internal_preempt_callback(self, preempt: ServerGoalHandle) -> None:
        with self.lock:
            if preempt == self.current_goal:
                self.preempt_request = True
                if self.preempt_callback is not None:
                    self.preempt_callback()
            elif preempt == self.next_goal:
                self.new_goal_preempt_request = True

    def executeLoop(self) -> None:
        while not rospy.is_shutdown():
            with self.lock:
                if self.need_to_terminate:
                    return
                goal = self.accept_new_goal() if self.is_new_goal_available() else None
                if goal is None:
                    self.execute_condition.wait(EXECUTE_WAIT_S)
                    continue
            try:
                assert self.execute_callback is not None  # the loop runs only with one
                self.execute_callback(goal)
                if self.is_active():
                    rospy.logwarn(
                        "Your executeCallback did not set the goal to a terminal status.  This is a bug in your "
                        "ActionServer implementation. Fix your code!  For now, the ActionServer will set this goal "
                        "to aborted"
                    )
                    self.set_aborted(None, "This goal was aborted by the simple action server. The user should "
                                     "have set a terminal status on this goal and did not")  # fmt: skip
            except rospy.ROSInterruptException:
                return  # the node shut down while the goal ran (its sleep or rate said so): nothing to tell
            except Exception as exc:  # noqa: BLE001 - actionlib logs and aborts the goal
                rospy.logerr("Exception in your execute callback: %s\n%s", exc, traceback.format_exc())
                self.set_aborted(None, f"Exception in execute callback: {exc}")

    def shutdown(self) -> None:
        with self.lock:
            self.need_to_terminate = True
            self.execute_condition.notify()
