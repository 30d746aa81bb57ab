"""rclpy.action.client."""
from __future__ import annotations

from typing import Any, Callable

from app.rosclient import actions, process
from rclpy import executors
from rclpy.task import Future


class FeedbackMessage:
    """What a feedback callback gets: `.feedback` is the action's Feedback."""

    def __init__(self, feedback: Any, goal_id: Any) -> None:
        self.feedback, self.goal_id = feedback, goal_id


class ResultResponse:
    """What get_result_async's future holds: `.status` (action_msgs/GoalStatus) and `.result`."""

    def __init__(self, status: int, result: Any) -> None:
        self.status, self.result = status, result


class CancelResponse:
    ERROR_NONE, ERROR_REJECTED, ERROR_UNKNOWN_GOAL_ID, ERROR_GOAL_TERMINATED = 0, 1, 2, 3

    def __init__(self, return_code: int) -> None:
        self.return_code = return_code
        self.goals_canceling = []


class ClientGoalHandle:
    def __init__(self, client: "ActionClient", call: actions.GoalCall) -> None:
        self._client, self._call = client, call
        self._result_future: Future | None = None

    @property
    def accepted(self) -> bool:
        return not (self._call.done.is_set() and self._call.error and self._call.status == actions.STATUS_ABORTED
                    and self._call.error.startswith("goal rejected"))

    @property
    def goal_id(self) -> Any:
        return self._call.id

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
        code = CancelResponse.ERROR_GOAL_TERMINATED if self._call.done.is_set() else CancelResponse.ERROR_NONE
        self._call.cancel()
        executors.post(self._client.node, lambda: future.set_result(CancelResponse(code)))
        return future

    def cancel_goal(self) -> CancelResponse:
        code = CancelResponse.ERROR_GOAL_TERMINATED if self._call.done.is_set() else CancelResponse.ERROR_NONE
        self._call.cancel()
        return CancelResponse(code)

    def _completed(self) -> None:
        if self._result_future is not None and not self._result_future.done():
            self._result_future.set_result(ResultResponse(self._call.status, self._call.result))


class ActionClient:
    def __init__(self, node: Any, action_type: Any, action_name: str, **options: Any) -> None:
        self.node, self.action_type = node, action_type
        self.name = node.resolve_topic_name(action_name)

    def server_is_ready(self) -> bool:
        return actions.server_ready(self.name)

    def wait_for_server(self, timeout_sec: float | None = None) -> bool:
        return process.wait_until(self.server_is_ready, timeout_sec)

    def send_goal_async(self, goal: Any, feedback_callback: Callable | None = None,
                        goal_uuid: Any = None) -> Future:
        if not isinstance(goal, self.action_type.Goal):
            raise TypeError(f"Expected {self.action_type.Goal._type}, got {type(goal)}")
        node, future = self.node, Future()
        holder: list[ClientGoalHandle] = []

        def feedback(message: Any) -> None:
            if feedback_callback is not None:
                executors.post(node, lambda: feedback_callback(FeedbackMessage(message, holder[0].goal_id)))

        def result(call: actions.GoalCall) -> None:
            executors.post(node, holder[0]._completed)

        call = actions.GoalCall(self.name, self.action_type, goal, feedback, result)
        holder.append(ClientGoalHandle(self, call))
        executors.post(node, lambda: future.set_result(holder[0]))
        return future

    def send_goal(self, goal: Any, feedback_callback: Callable | None = None, goal_uuid: Any = None) -> ResultResponse:
        call = actions.GoalCall(self.name, self.action_type, goal,
                                (lambda m: feedback_callback(FeedbackMessage(m, None))) if feedback_callback else None)
        call.done.wait()
        return ResultResponse(call.status, call.result)

    def destroy(self) -> None:
        pass
