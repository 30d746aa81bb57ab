"""rclpy.action.client: ActionClient as rclpy has it, over rosbridge's ROS 2 action ops
(rosclient/actions.py). The client is a waitable of its node: the goal's handle, feedback, the
result and a cancel's answer complete their futures and callbacks inside spin.

rosbridge's cancel_action_goal has no answer of its own, so a cancel's response comes with the
goal's end: canceled, the cancel was accepted (`goals_canceling` holds the goal); ended otherwise,
it was rejected (ERROR_REJECTED; ERROR_GOAL_TERMINATED when the goal had ended before the cancel).
"""

from __future__ import annotations

import time
import uuid
from collections import deque
from collections.abc import Callable
from typing import Any

from rosclient import actions, process
from rclpy import _endpoints, context
from rclpy._entity import Call
from rclpy.callback_groups import CallbackGroup
from rclpy.task import Future
from rclpy.waitable import Waitable


class FeedbackMessage:
    """What a feedback callback gets: `.feedback` is the action's Feedback, `.goal_id` the goal's UUID."""

    def __init__(self, feedback: Any, goal_id: Any) -> None:
        self.feedback, self.goal_id = feedback, goal_id


class ResultResponse:
    """What get_result_async's future holds: `.status` (action_msgs/GoalStatus) and `.result`."""

    def __init__(self, status: int, result: Any) -> None:
        self.status, self.result = status, result


def _goal_info(goal_id: Any) -> Any:
    from action_msgs.msg import GoalInfo

    stamp = time.time_ns()
    info = GoalInfo(goal_id=goal_id)
    info.stamp.sec, info.stamp.nanosec = stamp // 10**9, stamp % 10**9
    return info


def cancel_response(return_code: int, canceling: list[Any]) -> Any:
    from action_msgs.srv import CancelGoal

    return CancelGoal.Response(return_code=return_code, goals_canceling=canceling)


class ClientGoalHandle:
    def __init__(self, action_client: ActionClient, call: actions.GoalCall, goal_id: Any) -> None:
        self._action_client, self._call, self._goal_id = action_client, call, goal_id
        self._result_future: Future | None = None
        self._cancel_futures: list[tuple[Future, bool]] = []  # (future, the goal had ended before)

    @property
    def accepted(self) -> bool:
        call = self._call
        return not (call.done.is_set() and call.status == actions.STATUS_ABORTED and call.error.startswith("goal rejected"))

    @property
    def goal_id(self) -> Any:
        return self._goal_id

    @property
    def stamp(self) -> Any:
        return _goal_info(self._goal_id).stamp

    @property
    def status(self) -> int:
        return self._call.status

    def get_result_async(self) -> Future:
        if self._result_future is None:
            self._result_future = Future()
            if self._call.done.is_set():
                self._result_future.set_result(ResultResponse(self._call.status, self._call.result))
        return self._result_future

    def get_result(self) -> ResultResponse:
        self._call.done.wait()
        return ResultResponse(self._call.status, self._call.result)

    def cancel_goal_async(self) -> Future:
        future = Future()
        ended = self._call.done.is_set()
        self._cancel_futures.append((future, ended))
        if ended:
            self._action_client._post(self._answer_cancels)
        else:
            self._call.cancel()
        return future

    def cancel_goal(self) -> Any:
        ended = self._call.done.is_set()
        self._call.cancel()
        self._call.done.wait()
        return self._cancel_answer(ended)

    def _cancel_answer(self, ended_before: bool) -> Any:
        if ended_before:
            return cancel_response(3, [])  # ERROR_GOAL_TERMINATED
        if self._call.status == actions.STATUS_CANCELED:
            return cancel_response(0, [_goal_info(self._goal_id)])  # ERROR_NONE
        return cancel_response(1, [])  # ERROR_REJECTED

    def _answer_cancels(self) -> None:
        answered, self._cancel_futures = self._cancel_futures, []
        for future, ended_before in answered:
            if not future.done():
                future.set_result(self._cancel_answer(ended_before))

    def _completed(self) -> None:
        """The result arrived (inside spin): the result's future, then the cancels' answers."""
        if self._result_future is not None and not self._result_future.done():
            self._result_future.set_result(ResultResponse(self._call.status, self._call.result))
        self._answer_cancels()


class ActionClient(Waitable):
    def __init__(self, node: Any, action_type: Any, action_name: str, *,
                 callback_group: CallbackGroup | None = None, **qos: Any) -> None:
        super().__init__(callback_group or node.default_callback_group)
        self._node, self.action_type = node, action_type
        self.name = node.resolve_topic_name(action_name)
        self._events: deque[Callable[[], Any]] = deque()
        self._node_name: str | None = node.get_fully_qualified_name()
        node.add_waitable(self)
        _endpoints.add_client(self.name, self._node_name, "action_client")  # `action info` counts it

    def _post(self, event: Callable[[], Any]) -> None:
        """Run `event` inside spin (from any thread)."""
        with context.CONDITION:
            self._events.append(event)
        context.wake()

    def _is_ready(self) -> bool:
        return bool(self._events)

    def _take(self) -> Call | None:
        with context.CONDITION:
            return self._events.popleft() if self._events else None

    def server_is_ready(self) -> bool:
        return actions.server_ready(self.name)

    def wait_for_server(self, timeout_sec: float | None = None) -> bool:
        return process.wait_until(self.server_is_ready, timeout_sec)

    def _goal_id(self, goal_uuid: Any) -> Any:
        from unique_identifier_msgs.msg import UUID

        if goal_uuid is None:
            return UUID(uuid=list(uuid.uuid4().bytes))
        return goal_uuid

    def send_goal_async(self, goal: Any, feedback_callback: Callable[..., Any] | None = None,
                        goal_uuid: Any = None) -> Future:
        if not isinstance(goal, self.action_type.Goal):
            raise TypeError(f"Expected {self.action_type.Goal._type}, got {type(goal)}")
        goal_id = self._goal_id(goal_uuid)
        future = Future()
        holder: list[ClientGoalHandle] = []

        def feedback(message: Any) -> None:
            if feedback_callback is not None:
                self._post(lambda: feedback_callback(FeedbackMessage(message, goal_id)))

        def result(call: actions.GoalCall) -> None:
            self._post(holder[0]._completed)

        call = actions.GoalCall(self.name, self.action_type, goal, feedback, result)
        holder.append(ClientGoalHandle(self, call, goal_id))
        self._post(lambda: future.set_result(holder[0]))
        return future

    def send_goal(self, goal: Any, feedback_callback: Callable[..., Any] | None = None,
                  goal_uuid: Any = None) -> ResultResponse:
        goal_id = self._goal_id(goal_uuid)
        call = actions.GoalCall(self.name, self.action_type, goal,
                                (lambda m: feedback_callback(FeedbackMessage(m, goal_id))) if feedback_callback else None)
        call.done.wait()
        return ResultResponse(call.status, call.result)

    def destroy(self) -> None:
        self._node.remove_waitable(self)
        if self._node_name is not None:
            _endpoints.remove_client(self.name, self._node_name, "action_client")
            self._node_name = None
