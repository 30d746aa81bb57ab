"""rclpy.action.server: ActionServer as rclpy has it, over rosbridge's ROS 2 action ops
(rosclient/actions.py).

The server is a waitable of its node: goal and cancel requests wait in it and run inside spin.
A goal request goes to `goal_callback` (accept or reject), an accepted goal to
`handle_accepted_callback` (by default `goal_handle.execute()`; a deferred, queued or single-goal
server calls `execute()` later itself), and `execute()` runs the execute callback: an `async def` one
as a task of the node's executor (it may await futures; a sync one on a thread of its own, so a
cancel reaches it while it sleeps, whatever the executor). A cancel request goes to
`cancel_callback` (rclpy's default rejects); accepted, the goal is CANCELING and the execute callback
sees `is_cancel_requested`. The result is sent when the execute callback returns, with the state it
left the goal in (none: aborted, as rclpy warns). Goal states move as rcl_action's state machine
allows; another move raises RCLError.
"""

from __future__ import annotations

import inspect
import threading
import traceback
from collections import deque
from collections.abc import Callable
from enum import Enum
from typing import Any

from rosclient import actions
from rclpy import context
from rclpy._entity import Call, await_or_execute
from rclpy.callback_groups import CallbackGroup
from rclpy.exceptions import RCLError
from rclpy.waitable import Waitable


class GoalResponse(Enum):
    REJECT = 1
    ACCEPT = 2


class CancelResponse(Enum):
    REJECT = 1
    ACCEPT = 2


class GoalEvent(Enum):
    EXECUTE = "EXECUTE"
    CANCEL_GOAL = "CANCEL_GOAL"
    SUCCEED = "SUCCEED"
    ABORT = "ABORT"
    CANCELED = "CANCELED"


STATE_NAMES = {0: "UNKNOWN", 1: "ACCEPTED", 2: "EXECUTING", 3: "CANCELING", 4: "SUCCEEDED", 5: "CANCELED",
               6: "ABORTED"}
# rcl_action's goal state machine: (state, event) -> the next state
TRANSITIONS = {
    (actions.STATUS_ACCEPTED, GoalEvent.EXECUTE): actions.STATUS_EXECUTING,
    (actions.STATUS_ACCEPTED, GoalEvent.CANCEL_GOAL): actions.STATUS_CANCELING,
    (actions.STATUS_EXECUTING, GoalEvent.CANCEL_GOAL): actions.STATUS_CANCELING,
    (actions.STATUS_EXECUTING, GoalEvent.SUCCEED): actions.STATUS_SUCCEEDED,
    (actions.STATUS_EXECUTING, GoalEvent.ABORT): actions.STATUS_ABORTED,
    (actions.STATUS_CANCELING, GoalEvent.SUCCEED): actions.STATUS_SUCCEEDED,
    (actions.STATUS_CANCELING, GoalEvent.ABORT): actions.STATUS_ABORTED,
    (actions.STATUS_CANCELING, GoalEvent.CANCELED): actions.STATUS_CANCELED,
}


def default_goal_callback(goal_request: Any) -> GoalResponse:
    return GoalResponse.ACCEPT


def default_handle_accepted_callback(goal_handle: ServerGoalHandle) -> None:
    goal_handle.execute()


def default_cancel_callback(cancel_request: Any) -> CancelResponse:
    return CancelResponse.REJECT  # rclpy's default: a server must opt in to cancelling


class ServerGoalHandle:
    def __init__(self, action_server: ActionServer, goal: actions.ServedGoal) -> None:
        self._action_server, self._goal = action_server, goal
        self._status = actions.STATUS_ACCEPTED
        self._lock = threading.Lock()

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

    def _update_state(self, event: GoalEvent) -> None:
        with self._lock:
            following = TRANSITIONS.get((self._status, event))
            if following is None:
                raise RCLError(f"goal_handle attempted invalid transition from state "
                               f"{STATE_NAMES[self._status]} with event {event.value}")
            self._status = following

    def execute(self, execute_callback: Callable[..., Any] | None = None) -> None:
        if self._status != actions.STATUS_EXECUTING:  # a canceling goal's execute raises, as in rcl_action
            self._update_state(GoalEvent.EXECUTE)
        self._action_server.notify_execute(self, execute_callback)

    def publish_feedback(self, feedback: Any) -> None:
        if not self.is_active:
            raise RCLError("Failed to publish feedback: the goal is not active")
        self._goal.publish_feedback(feedback)

    def succeed(self) -> None:
        self._update_state(GoalEvent.SUCCEED)

    def abort(self) -> None:
        self._update_state(GoalEvent.ABORT)

    def canceled(self) -> None:
        self._update_state(GoalEvent.CANCELED)

    def destroy(self) -> None:
        pass


class ActionServer(Waitable):
    def __init__(self, node: Any, action_type: Any, action_name: str, execute_callback: Callable[..., Any], *,
                 callback_group: CallbackGroup | None = None,
                 goal_callback: Callable[..., Any] = default_goal_callback,
                 handle_accepted_callback: Callable[..., Any] = default_handle_accepted_callback,
                 cancel_callback: Callable[..., Any] = default_cancel_callback, **qos: Any) -> None:
        super().__init__(callback_group or node.default_callback_group)
        self._node, self.action_type = node, action_type
        self.register_execute_callback(execute_callback)
        self.register_goal_callback(goal_callback)
        self.register_handle_accepted_callback(handle_accepted_callback)
        self.register_cancel_callback(cancel_callback)
        self.name = node.resolve_topic_name(action_name)
        self._handles: dict[Any, ServerGoalHandle] = {}
        self._requests: deque[tuple[str, actions.ServedGoal]] = deque()
        self._serving = actions.ActionServing(self.name, action_type, self._on_goal, self._on_cancel)
        node.add_waitable(self)

    def register_execute_callback(self, execute_callback: Callable[..., Any]) -> None:
        if not callable(execute_callback):
            raise TypeError("Failed to register goal execution callback: not callable")
        self._execute_callback = execute_callback

    def register_goal_callback(self, goal_callback: Callable[..., Any] | None) -> None:
        self._goal_callback = goal_callback or default_goal_callback

    def register_handle_accepted_callback(self, handle_accepted_callback: Callable[..., Any] | None) -> None:
        self._handle_accepted_callback = handle_accepted_callback or default_handle_accepted_callback

    def register_cancel_callback(self, cancel_callback: Callable[..., Any] | None) -> None:
        self._cancel_callback = cancel_callback or default_cancel_callback

    # --- requests from the lab (the connection's reader thread), taken inside spin ---------------
    def _on_goal(self, goal: actions.ServedGoal) -> None:
        with context.CONDITION:
            self._requests.append(("goal", goal))
        context.wake()

    def _on_cancel(self, goal: actions.ServedGoal) -> None:
        with context.CONDITION:
            self._requests.append(("cancel", goal))
        context.wake()

    def _is_ready(self) -> bool:
        return bool(self._requests)

    def _take(self) -> Call | None:
        with context.CONDITION:
            if not self._requests:
                return None
            kind, goal = self._requests.popleft()
        if kind == "goal":
            return lambda: self._goal_request(goal)
        return lambda: self._cancel_request(goal)

    async def _goal_request(self, goal: actions.ServedGoal) -> None:
        if await await_or_execute(self._goal_callback, goal.request) != GoalResponse.ACCEPT:
            goal.reject("goal rejected by the action server")
            return
        handle = self._handles[goal.id] = ServerGoalHandle(self, goal)
        await await_or_execute(self._handle_accepted_callback, handle)

    async def _cancel_request(self, goal: actions.ServedGoal) -> None:
        handle = self._handles.get(goal.id)
        if handle is None or not handle.is_active:
            return
        if await await_or_execute(self._cancel_callback, handle) == CancelResponse.ACCEPT and handle.is_active:
            if not handle.is_cancel_requested:
                handle._update_state(GoalEvent.CANCEL_GOAL)

    # --- executing a goal ------------------------------------------------------------------------
    def notify_execute(self, goal_handle: ServerGoalHandle, execute_callback: Callable[..., Any] | None) -> None:
        callback = execute_callback or self._execute_callback
        if inspect.iscoroutinefunction(callback):
            executor = self._node.executor
            if executor is None:
                import rclpy

                executor = rclpy.get_global_executor()
            executor.create_task(self._execute_goal, callback, goal_handle)
        else:
            threading.Thread(target=self._execute_sync, args=(callback, goal_handle), daemon=True,
                             name=f"action{self.name}").start()

    async def _execute_goal(self, callback: Callable[..., Any], goal_handle: ServerGoalHandle) -> None:
        try:
            result = await await_or_execute(callback, goal_handle)
        except Exception as exc:  # noqa: BLE001 - the goal is aborted with the reason, the server goes on
            traceback.print_exc()
            self._failed(goal_handle, exc)
            return
        self._send_result(goal_handle, result)

    def _execute_sync(self, callback: Callable[..., Any], goal_handle: ServerGoalHandle) -> None:
        try:
            result = callback(goal_handle)
        except Exception as exc:  # noqa: BLE001 - as above
            traceback.print_exc()
            self._failed(goal_handle, exc)
            return
        self._send_result(goal_handle, result)

    def _failed(self, goal_handle: ServerGoalHandle, exc: Exception) -> None:
        self._handles.pop(goal_handle.goal_id, None)
        goal_handle._goal.reject(f"{type(exc).__name__}: {exc}")

    def _send_result(self, goal_handle: ServerGoalHandle, result: Any) -> None:
        self._handles.pop(goal_handle.goal_id, None)
        if result is None:
            result = self.action_type.Result()
        if not isinstance(result, self.action_type.Result):
            goal_handle._goal.reject(f"execute_callback returned {result!r}, not a {self.action_type.Result._type}")
            return
        if goal_handle.is_active:
            self._node.get_logger().warning(f"Goal state not set, assuming aborted. Goal ID: {goal_handle.goal_id}")
            with goal_handle._lock:
                goal_handle._status = actions.STATUS_ABORTED
        goal_handle._goal.finish(goal_handle.status, result)

    def destroy(self) -> None:
        self._node.remove_waitable(self)
        self._serving.close()
