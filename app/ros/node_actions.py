"""Actions provided by nodes (rosbridge's ROS 2 `advertise_action` family, as rosbridge_suite's
advertise_action.py implements it): a client advertises an action, the lab lists it with its own
(GET /actions, `action list`, the dashboard, rosapi's action_servers) and every goal — HTTP, the
CLI, the page, another client — goes through the same ActionServer, with actionlib's states.

A goal's life, as the provider sees it (the message shapes of rosbridge_suite):
- the lab sends {"op": "send_action_goal", "id": GOAL_ID, "action": NAME, "action_type": TYPE,
  "args": {goal fields}, "feedback": true};
- the provider answers with any number of {"op": "action_feedback", "id": GOAL_ID, "action": NAME,
  "values": {feedback fields}} and one {"op": "action_result", "id": GOAL_ID, "action": NAME,
  "values": {result fields}, "status": S, "result": true}: S is action_msgs/GoalStatus, 4 succeeded
  (SUCCEEDED), 5 canceled (PREEMPTED, with the values as its result), 6 aborted (ABORTED);
  `"result": false` aborts the goal, whatever the status;
- a cancel (HTTP, CLI, page, client) sends {"op": "cancel_action_goal", "id": GOAL_ID, "action":
  NAME} once; the goal stays PREEMPTING until the provider's action_result.
The provider that unadvertises or disconnects takes its actions with it: its goals end ABORTED.
Goals, feedback and results are checked against the action type's models when the lab knows the
type (its own actions'); a type it does not know passes them through as JSON objects.
"""

from __future__ import annotations

import asyncio
import itertools
import threading
from concurrent.futures import Future
from concurrent.futures import TimeoutError as WaitTimeout
from dataclasses import dataclass, field
from typing import Any

from pydantic import ValidationError

from app.ros.actions import Action, ActionServer, GoalFailure, GoalHandle, GoalPreempted, GoalSucceeded
from app.ros.messages import RosMessage, validation_reason
from app.ros.node_services import NodeClient, OpenMessage, normalise_type

POLL_S = 0.02  # how often a goal's thread looks for a cancel while it waits for the node
# action_msgs/GoalStatus codes an action_result may carry
SUCCEEDED, CANCELED, ABORTED = 4, 5, 6


@dataclass
class Pending:
    """A goal sent to a node and not yet answered."""

    session: NodeClient
    action: Action
    handle: GoalHandle
    result: Future = field(default_factory=Future)  # (values, status, ok)


class NodeActions:
    def __init__(self, server: ActionServer) -> None:
        self.server = server
        self.declared = set(server.actions)  # the lab's own actions
        self.types = {a.type: (a.goal, a.result, a.feedback) for a in server.actions.values()}
        self.providers: dict[str, NodeClient] = {}  # action name -> its node
        self.pending: dict[str, Pending] = {}  # goal id -> the goal at its node
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    def advertise(self, name: str, type_name: str, session: NodeClient) -> None:
        """A node provides action `name`; ValueError with the reason it cannot."""
        with self._lock:
            if name in self.declared:
                raise ValueError(f"action {name} is the lab's")
            current = self.providers.get(name)
            if current is not None and current is not session:
                raise ValueError(f"action {name} is already provided by node {current.name}")
            goal, result, feedback = self.types.get(normalise_type(type_name), (OpenMessage, OpenMessage, OpenMessage))
            unknown = (
                ""
                if goal is not OpenMessage
                else (
                    f"; type {type_name} is unknown to the lab: goal, feedback and result pass through as JSON objects"
                )
            )
            self.server.remove(name)
            self.server.add(
                Action(
                    name,
                    type_name,
                    goal,
                    result,
                    feedback,
                    self._execute(name),
                    f"provided by node {session.name}{unknown}",
                    concurrent_goals=True,
                )
            )
            self.providers[name] = session

    def unadvertise(self, name: str, session: NodeClient) -> bool:
        with self._lock:
            provider = self.providers.get(name)
            if provider is not session:
                return False
            del self.providers[name]
            self.server.remove(name)
            gone = [p for p in self.pending.values() if p.action.name == name]
        for pending in gone:
            _settle(pending.result, GoalFailure(f"node {session.name} withdrew action {name} before the goal ended"))
        return True

    def drop(self, session: NodeClient) -> None:
        """A node disconnected: its actions go with it."""
        for name in [n for n, s in list(self.providers.items()) if s is session]:
            self.unadvertise(name, session)

    # --- a goal at its node -------------------------------------------------------------------
    def _execute(self, name: str):
        def execute(lab, goal: RosMessage, handle: GoalHandle) -> RosMessage:
            with self._lock:
                session = self.providers.get(name)
                action = self.server.get(name)
                if session is None or action is None:
                    raise GoalFailure(f"action {name} is not provided any more")
                goal_id = f"action_goal:{name}:{next(self._ids)}"
                pending = self.pending[goal_id] = Pending(session, action, handle)
            try:
                self._send(
                    session,
                    {
                        "op": "send_action_goal",
                        "id": goal_id,
                        "action": name,
                        "action_type": action.type,
                        "args": goal.model_dump(by_alias=True),
                        "feedback": True,
                    },
                )
                canceling = False
                while True:
                    try:
                        values, status, ok = pending.result.result(timeout=POLL_S)
                        break
                    except WaitTimeout:
                        if handle.cancel_requested and not canceling:
                            canceling = True
                            self._send(session, {"op": "cancel_action_goal", "id": goal_id, "action": name})
            finally:
                with self._lock:
                    self.pending.pop(goal_id, None)
            if not ok or status == ABORTED:
                raise GoalFailure(
                    f"aborted by node {session.name}" + (f": {values}" if values not in (None, {}) else "")
                )
            result = _model(action.result, values, f"the node's result is not a {action.type} result")
            if status == CANCELED:
                raise GoalPreempted(result, f"canceled by node {session.name}")
            if status != SUCCEEDED:
                raise GoalFailure(
                    f"node {session.name} ended the goal with status {status} (4 succeeded, 5 canceled, 6 aborted)"
                )
            if handle.cancel_requested:  # the node rejected the cancel: its goal succeeded
                raise GoalSucceeded(result)
            return result

        return execute

    @staticmethod
    def _send(session: NodeClient, message: dict) -> None:
        if session.loop is None:  # not connected yet (a session's loop is set when it runs)
            raise GoalFailure(f"node {session.name} is not connected")
        try:
            asyncio.run_coroutine_threadsafe(session.send(message), session.loop)
        except RuntimeError as exc:  # the node's connection is closing
            raise GoalFailure(f"node {session.name} is gone ({exc})") from None

    def _pending(self, session: NodeClient, goal_id: object, name: str) -> Pending:
        with self._lock:
            pending = self.pending.get(goal_id) if isinstance(goal_id, str) else None
        if pending is None or pending.session is not session or pending.action.name != name:
            raise ValueError(f"no goal with id {str(goal_id)[:80]} of action {name} waits for this client")
        return pending

    def feedback(self, session: NodeClient, goal_id: object, name: str, values: Any) -> None:
        """A node's action_feedback; ValueError naming what is wrong."""
        pending = self._pending(session, goal_id, name)
        pending.handle.feedback(
            _model(pending.action.feedback, values, f"not a {pending.action.type} feedback", error=ValueError)
        )

    def result(self, session: NodeClient, goal_id: object, name: str, values: Any, status: int, ok: bool) -> None:
        """A node's action_result; ValueError when no goal of this node waits for it."""
        pending = self._pending(session, goal_id, name)
        _settle(pending.result, (values, status, ok))


def _model(model, values: Any, what: str, error: type[Exception] = GoalFailure) -> RosMessage:
    try:
        return model.model_validate(values if values is not None else {})
    except ValidationError as exc:
        raise error(f"{what} ({validation_reason(exc, 'values')})") from None


def _settle(future: Future, outcome: Any) -> None:
    if future.done():
        return
    if isinstance(outcome, Exception):
        future.set_exception(outcome)
    else:
        future.set_result(outcome)
