"""actionlib's ServerGoalHandle: one goal an ActionServer tracks, its status (actionlib_msgs/GoalStatus)
moved as actionlib's state machine allows (a transition it does not allow is logged and ignored)."""

from __future__ import annotations

import threading
from typing import Any, Protocol

import rospy
from actionlib_msgs.msg import GoalID, GoalStatus


class ActionServer(Protocol):
    """What a handle asks of the server that tracks it (actionlib/action_server.py)."""

    lock: threading.RLock

    def publish_status(self) -> None: ...

    def publish_result(self, handle: ServerGoalHandle, result: Any) -> None: ...

    def publish_feedback(self, handle: ServerGoalHandle, feedback: Any) -> None: ...

PENDING, ACTIVE, PREEMPTED, SUCCEEDED = GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.PREEMPTED, GoalStatus.SUCCEEDED
ABORTED, REJECTED, PREEMPTING = GoalStatus.ABORTED, GoalStatus.REJECTED, GoalStatus.PREEMPTING
RECALLING, RECALLED = GoalStatus.RECALLING, GoalStatus.RECALLED
TERMINAL = (PREEMPTED, SUCCEEDED, ABORTED, REJECTED, RECALLED)


class ServerGoalHandle:
    """A goal's handle; an empty one (no server) stands for "no goal", as actionlib's default handle."""

    def __init__(self, server: ActionServer | None = None, action_goal: Any = None, origin: Any = None) -> None:
        # the goal as it came (XActionGoal: goal_id, goal), as actionlib's handle keeps it; origin: the
        # lab's op that brought it, or None (the action's goal topic)
        self.server, self.goal, self.origin = server, action_goal, origin
        goal_id = action_goal.goal_id if action_goal is not None else GoalID()
        self.status = GoalStatus(goal_id=goal_id, status=PENDING)
        self.destroy_time: float | None = None  # when it left the status list's tracking (terminal)

    def get_goal(self) -> Any:
        return None if self.goal is None else self.goal.goal

    def get_goal_id(self) -> Any:
        return self.status.goal_id

    def get_goal_status(self) -> Any:
        return self.status

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ServerGoalHandle) or self.goal is None or other.goal is None:
            return False
        return bool(self.status.goal_id.id == other.status.goal_id.id)

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(self.status.goal_id.id)

    # --- transitions ------------------------------------------------------------------------
    def _move(self, allowed: dict[int, int], what: str, text: str) -> bool:
        server = self.server
        if server is None:
            rospy.logerr("Attempt to %s on an uninitialized ServerGoalHandle", what)
            return False
        with server.lock:
            current = self.status.status
            if current not in allowed:
                rospy.logerr(
                    "To transition to %s, the goal must be in one of the states %s, it is currently in state: %d",
                    what,
                    sorted(allowed),
                    current,
                )
                return False
            self.status.status, self.status.text = allowed[current], text
            return True

    def set_accepted(self, text: str = "") -> None:
        if self._move({PENDING: ACTIVE, RECALLING: PREEMPTING}, "an active state", text):
            self._server().publish_status()

    def set_cancel_requested(self) -> bool:
        return self._move({PENDING: RECALLING, ACTIVE: PREEMPTING}, "a cancel-requested state", self.status.text)

    def set_rejected(self, result: Any = None, text: str = "") -> None:
        if self._move({PENDING: REJECTED, RECALLING: REJECTED}, "a rejected state", text):
            self._server().publish_result(self, result)

    def set_canceled(self, result: Any = None, text: str = "") -> None:
        moves = {PENDING: RECALLED, RECALLING: RECALLED, ACTIVE: PREEMPTED, PREEMPTING: PREEMPTED}
        if self._move(moves, "a canceled state", text):
            self._server().publish_result(self, result)

    def set_succeeded(self, result: Any = None, text: str = "") -> None:
        if self._move({ACTIVE: SUCCEEDED, PREEMPTING: SUCCEEDED}, "a succeeded state", text):
            self._server().publish_result(self, result)

    def set_aborted(self, result: Any = None, text: str = "") -> None:
        if self._move({ACTIVE: ABORTED, PREEMPTING: ABORTED}, "an aborted state", text):
            self._server().publish_result(self, result)

    def publish_feedback(self, feedback: Any) -> None:
        if self.server is None:
            rospy.logerr("Attempt to publish feedback on an uninitialized ServerGoalHandle")
            return
        self.server.publish_feedback(self, feedback)

    def _server(self) -> ActionServer:
        assert self.server is not None  # _move refused a handle without one
        return self.server
