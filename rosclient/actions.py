"""Actions over rosbridge's ROS 2 ops, shared by rclpy.action and actionlib.

Client: send_action_goal (feedback on) -> action_feedback ... action_result {status, values, result};
cancel_action_goal. Server: advertise_action; the lab sends send_action_goal / cancel_action_goal,
the program answers with action_feedback and action_result. Status codes are action_msgs/GoalStatus
(4 succeeded, 5 canceled, 6 aborted); actionlib's (3 succeeded, 2 preempted, 4 aborted) are mapped
from them in actionlib.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from rosclient import process

STATUS_UNKNOWN, STATUS_ACCEPTED, STATUS_EXECUTING, STATUS_CANCELING = 0, 1, 2, 3
STATUS_SUCCEEDED, STATUS_CANCELED, STATUS_ABORTED = 4, 5, 6


def type_name(action_class: Any) -> str:
    return getattr(action_class, "_action_type", "") or action_class._type


def server_ready(name: str) -> bool:
    return name in process.action_names()


class GoalCall:
    """One goal sent to an action server: feedback and the result come to the callbacks (from the
    connection's reader thread); `done` is set with the result."""

    def __init__(
        self,
        name: str,
        action_class: Any,
        goal: Any,
        on_feedback: Callable[[Any], None] | None = None,
        on_result: Callable[[GoalCall], None] | None = None,
    ) -> None:
        self.name, self.action_class = name, action_class
        self.on_feedback, self.on_result = on_feedback, on_result
        self.done = threading.Event()
        self.status = STATUS_ACCEPTED
        self.result: Any = None
        self.error = ""
        self.id = process.connection().send_action_goal(
            name, type_name(action_class), goal.to_json(), self._feedback, self._result
        )

    def _feedback(self, message: dict) -> None:
        self.status = STATUS_EXECUTING
        if self.on_feedback is not None:
            self.on_feedback(self.action_class.Feedback.from_json(message.get("values") or {}))

    def _result(self, message: dict) -> None:
        values = message.get("values")
        self.status = int(message.get("status", STATUS_ABORTED) or STATUS_ABORTED)
        if isinstance(values, dict):
            self.result = self.action_class.Result.from_json(values)
        else:
            self.result = self.action_class.Result()
            self.error = str(values or "")
            if not message.get("result", True) and self.status in (STATUS_SUCCEEDED, 0):
                self.status = STATUS_ABORTED
        self.done.set()
        if self.on_result is not None:
            self.on_result(self)

    def cancel(self) -> None:
        if not self.done.is_set():
            self.status = STATUS_CANCELING
            process.connection().cancel_action_goal(self.name, self.id)


class ServedGoal:
    """A goal the program's action server got: its request, cancel flag, feedback and result."""

    def __init__(self, server: ActionServing, message: dict) -> None:
        self.server, self.id = server, message.get("id")
        self.request = server.action_class.Goal.from_json(message.get("args") or {})
        self.cancel_requested = threading.Event()
        self.finished = False

    def publish_feedback(self, feedback: Any) -> None:
        if not isinstance(feedback, self.server.action_class.Feedback):
            raise TypeError(f"Expected {self.server.action_class.Feedback._type}, got {type(feedback)}")
        process.connection().send(
            {"op": "action_feedback", "id": self.id, "action": self.server.name, "values": feedback.to_json()}
        )

    def finish(self, status: int, result: Any) -> None:
        if self.finished:
            return
        self.finished = True
        values = result.to_json() if result is not None else self.server.action_class.Result().to_json()
        process.connection().send(
            {
                "op": "action_result",
                "id": self.id,
                "action": self.server.name,
                "values": values,
                "status": status,
                "result": True,
            }
        )
        self.server.goals.pop(self.id, None)

    def reject(self, reason: str) -> None:
        self.finished = True
        process.connection().send(
            {
                "op": "action_result",
                "id": self.id,
                "action": self.server.name,
                "values": reason,
                "status": STATUS_ABORTED,
                "result": False,
            }
        )
        self.server.goals.pop(self.id, None)


class ActionServing:
    """An action the program provides: each goal goes to `on_goal(ServedGoal)` (from the reader
    thread: the API decides where it runs); a cancel request to `on_cancel(ServedGoal)`."""

    def __init__(
        self,
        name: str,
        action_class: Any,
        on_goal: Callable[[ServedGoal], None],
        on_cancel: Callable[[ServedGoal], None],
    ) -> None:
        self.name, self.action_class = name, action_class
        self.on_goal, self.on_cancel = on_goal, on_cancel
        self.goals: dict[Any, ServedGoal] = {}
        process.connection().advertise_action(name, type_name(action_class), self._goal, self._cancel)

    def _goal(self, message: dict) -> None:
        goal = ServedGoal(self, message)
        self.goals[goal.id] = goal
        self.on_goal(goal)

    def _cancel(self, message: dict) -> None:
        goal = self.goals.get(message.get("id"))
        if goal is not None:
            self.on_cancel(goal)

    def close(self) -> None:
        process.connection().send({"op": "unadvertise_action", "action": self.name})
