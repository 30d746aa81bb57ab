"""rclpy.action.server."""
from __future__ import annotations

import threading
import traceback
from enum import Enum
from typing import Any, Callable

from app.rosclient import actions


class GoalResponse(Enum):
    REJECT = 1
    ACCEPT = 2


class CancelResponse(Enum):
    REJECT = 1
    ACCEPT = 2


def default_goal_callback(goal_request: Any) -> GoalResponse:
    return GoalResponse.ACCEPT


def default_cancel_callback(cancel_request: Any) -> CancelResponse:
    return CancelResponse.REJECT  # rclpy's default: a server must opt in to cancelling


class ServerGoalHandle:
    def __init__(self, goal: actions.ServedGoal) -> None:
        self._goal = goal
        self._status = actions.STATUS_ACCEPTED
        self._result_status: int | None = None

    @property
    def request(self) -> Any:
        return self._goal.request

    @property
    def goal_id(self) -> Any:
        return self._goal.id

    @property
    def is_active(self) -> bool:
        return self._status in (actions.STATUS_ACCEPTED, actions.STATUS_EXECUTING, actions.STATUS_CANCELING)

    @property
    def is_cancel_requested(self) -> bool:
        return self._status == actions.STATUS_CANCELING

    @property
    def status(self) -> int:
        return self._status

    def execute(self, execute_callback: Callable | None = None) -> None:
        self._status = actions.STATUS_EXECUTING

    def publish_feedback(self, feedback: Any) -> None:
        self._goal.publish_feedback(feedback)

    def succeed(self) -> None:
        self._status = self._result_status = actions.STATUS_SUCCEEDED

    def abort(self) -> None:
        self._status = self._result_status = actions.STATUS_ABORTED

    def canceled(self) -> None:
        self._status = self._result_status = actions.STATUS_CANCELED

    def destroy(self) -> None:
        pass


class ActionServer:
    def __init__(self, node: Any, action_type: Any, action_name: str, execute_callback: Callable, *,
                 callback_group: Any = None, goal_callback: Callable = default_goal_callback,
                 handle_accepted_callback: Callable | None = None,
                 cancel_callback: Callable = default_cancel_callback, **qos: Any) -> None:
        self.node, self.action_type = node, action_type
        self.execute_callback, self.goal_callback, self.cancel_callback = execute_callback, goal_callback, cancel_callback
        self.name = node.resolve_topic_name(action_name)
        self._handles: dict[Any, ServerGoalHandle] = {}
        self._serving = actions.ActionServing(self.name, action_type, self._on_goal, self._on_cancel)

    def _on_goal(self, goal: actions.ServedGoal) -> None:
        threading.Thread(target=self._run, args=(goal,), daemon=True, name=f"action{self.name}").start()

    def _run(self, goal: actions.ServedGoal) -> None:
        if self.goal_callback(goal.request) != GoalResponse.ACCEPT:
            goal.reject("goal rejected by the action server")
            return
        handle = self._handles[goal.id] = ServerGoalHandle(goal)
        handle.execute()
        try:
            result = self.execute_callback(handle)
        except Exception as exc:  # noqa: BLE001 - the goal is aborted with the reason, the server goes on
            traceback.print_exc()
            goal.reject(f"{type(exc).__name__}: {exc}")
            return
        finally:
            self._handles.pop(goal.id, None)
        if result is None:
            result = self.action_type.Result()
        if not isinstance(result, self.action_type.Result):
            goal.reject(f"execute_callback returned {result!r}, not a {self.action_type.Result._type}")
            return
        status = handle._result_status
        if status is None:
            self.node.get_logger().warn("Goal state not set, assuming aborted. Goal ID: {0}".format(goal.id))
            status = actions.STATUS_ABORTED
        goal.finish(status, result)

    def _on_cancel(self, goal: actions.ServedGoal) -> None:
        handle = self._handles.get(goal.id)
        if handle is not None and self.cancel_callback(goal) == CancelResponse.ACCEPT and handle.is_active:
            handle._status = actions.STATUS_CANCELING

    def destroy(self) -> None:
        self._serving.close()
