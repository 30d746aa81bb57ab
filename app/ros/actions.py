"""Actions as actionlib has them: goal / feedback / result / cancel, with the goal states
pending, active, preempting, succeeded, aborted, preempted, rejected.

One declaration per action (name, type, goal/result/feedback models, execute). Each action serves
one goal at a time: a goal sent while another is pending or active is REJECTED (the caller
cancels the running one first); an action with `concurrent_goals` (a node's, as ROS 2 servers
take every goal and queue, abort or run them side by side themselves) runs each goal it is sent. A goal runs in its own thread; `execute(lab, goal, handle)`
publishes feedback with `handle.feedback(...)`, checks `handle.cancel_requested` (or sleeps
with `handle.wait(s)`, which wakes on cancel) and returns the result. Returning while a cancel
is requested ends PREEMPTED; raising `GoalFailure` ends ABORTED with its message (any other
exception: ABORTED with its type and message); raising `GoalPreempted(result)` ends PREEMPTED with
that result; raising `GoalSucceeded(result)` ends SUCCEEDED whatever was requested; returning
ends SUCCEEDED. An action may declare
`precondition(lab, goal) -> reason or None`: a goal that cannot run now is REJECTED up front (409).

Over HTTP (app/api/actions.py): POST /actions/{name}/goals (typed goal) -> goal id and status;
GET .../goals/{id} (long-poll with ?after=N&wait=S for feedback beyond the N-th);
POST .../goals/{id}/cancel; WebSocket .../goals/{id}/stream (every feedback and the final state).
"""

import asyncio
import builtins
import threading
import time
import traceback
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from app.ros.messages import RosMessage, definition
from app.ros.names import absolute


class GoalFailure(Exception):
    """A goal that could not be done (the reason is the message, shown as it is)."""


class GoalPreempted(Exception):
    """Raised by `execute`: the goal ends PREEMPTED with this result (e.g. a node's server that
    canceled its goal and sent what it had)."""

    def __init__(self, result: RosMessage, message: str = "canceled") -> None:
        super().__init__(message)
        self.result = result


class GoalSucceeded(Exception):
    """Raised by `execute`: the goal ends SUCCEEDED with this result even though a cancel was
    requested (a node's server that rejected the cancel and finished its goal)."""

    def __init__(self, result: RosMessage) -> None:
        super().__init__("done")
        self.result = result


class GoalStatus(str, Enum):
    PENDING = "pending"
    ACTIVE = "active"
    PREEMPTING = "preempting"
    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    PREEMPTED = "preempted"
    REJECTED = "rejected"


TERMINAL = {GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.PREEMPTED, GoalStatus.REJECTED}


@dataclass(frozen=True)
class Action:
    name: str
    type: str
    goal: builtins.type[RosMessage]  # builtins.: the field `type` above shadows the builtin here
    result: builtins.type[RosMessage]
    feedback: builtins.type[RosMessage]
    execute: Callable[[Any, Any, "GoalHandle"], RosMessage]
    description: str = ""
    precondition: Callable[[Any, Any], str | None] | None = None  # (lab, goal) -> why it cannot run now
    concurrent_goals: bool = False  # True: goals run side by side (a node's server queues or aborts them itself)

    @property
    def definition(self) -> str:
        """The .action text: goal --- result --- feedback."""
        return "\n".join(
            part
            for part in (definition(self.goal), "---", definition(self.result), "---", definition(self.feedback))
            if part
        )


@dataclass
class GoalHandle:
    action: Action
    goal: RosMessage
    id: str = field(default_factory=lambda: uuid.uuid4().hex)
    status: GoalStatus = GoalStatus.PENDING
    feedbacks: list[dict] = field(default_factory=list)
    result: dict | None = None
    message: str = ""
    _changed: threading.Condition = field(default_factory=threading.Condition)
    _waiters: list[Callable[[], None]] = field(default_factory=list)  # asyncio waiters to wake

    @property
    def cancel_requested(self) -> bool:
        return self.status == GoalStatus.PREEMPTING

    def feedback(self, message: RosMessage) -> None:
        with self._changed:
            self.feedbacks.append(message.model_dump(by_alias=True))
            self.notify()

    def notify(self) -> None:
        """Wake every waiter, threads and asyncio tasks (call with _changed held)."""
        self._changed.notify_all()
        for wake in self._waiters:
            wake()

    def wait(self, seconds: float) -> bool:
        """Sleep up to `seconds`; True if a cancel was requested (then it returns at once)."""
        end = time.monotonic() + seconds
        with self._changed:
            while not self.cancel_requested:
                left = end - time.monotonic()
                if left <= 0:
                    break
                self._changed.wait(left)
        return self.cancel_requested

    def set_status(self, status: GoalStatus, message: str = "", result: dict | None = None) -> None:
        with self._changed:
            self.status = status
            self.message = message or self.message
            if result is not None:
                self.result = result
            self.notify()

    def wait_for_update(self, after: int, timeout: float) -> None:
        """Block until there is feedback beyond `after`, a terminal state, or timeout."""
        end = time.monotonic() + timeout
        with self._changed:
            while len(self.feedbacks) <= after and self.status not in TERMINAL:
                left = end - time.monotonic()
                if left <= 0:
                    return
                self._changed.wait(left)

    async def updated(self, after: int, timeout: float) -> None:
        """wait_for_update for the event loop: no thread is held while waiting."""
        loop = asyncio.get_running_loop()
        event = asyncio.Event()

        def wake() -> None:
            try:
                loop.call_soon_threadsafe(event.set)
            except RuntimeError:  # the loop is closed: nobody waits any more
                pass

        end = loop.time() + timeout
        with self._changed:
            self._waiters.append(wake)
        try:
            while True:
                with self._changed:
                    if len(self.feedbacks) > after or self.status in TERMINAL:
                        return
                    event.clear()
                left = end - loop.time()
                if left <= 0:
                    return
                try:
                    await asyncio.wait_for(event.wait(), left)
                except TimeoutError:
                    return
        finally:
            with self._changed:
                self._waiters.remove(wake)

    def view(self, after: int = 0) -> dict:
        with self._changed:
            return {
                "action": self.action.name,
                "goal_id": self.id,
                "status": self.status.value,
                "message": self.message,
                "goal": self.goal.model_dump(by_alias=True),
                "feedback_count": len(self.feedbacks),
                "feedback": self.feedbacks[after:],
                "result": self.result,
            }


class ActionServer:
    keep_goals = 100

    def __init__(self, actions: list[Action], lab: object) -> None:  # lab: handed to execute and precondition
        self.actions = {a.name: a for a in actions}
        self.lab = lab
        self.goals: dict[str, GoalHandle] = {}
        self._lock = threading.Lock()

    def get(self, name: str) -> Action | None:
        return self.actions.get(absolute(name))

    def add(self, action: Action) -> None:
        """An action added while the server runs (one a node provides)."""
        with self._lock:
            if action.name in self.actions:
                raise ValueError(f"action {action.name} exists already")
            self.actions[action.name] = action

    def remove(self, name: str) -> Action | None:
        with self._lock:
            return self.actions.pop(absolute(name), None)

    def goal(self, name: str, goal_id: str) -> GoalHandle | None:
        """The goal `goal_id` of action `name` (None if there is no such goal of that action)."""
        handle = self.goals.get(goal_id)
        return handle if handle is not None and handle.action.name == absolute(name) else None

    def send_goal(self, action: Action, goal: RosMessage) -> GoalHandle:
        handle = GoalHandle(action, goal)
        with self._lock:
            busy = [
                g
                for g in self.goals.values()
                if g.action is action and g.status not in TERMINAL and not action.concurrent_goals
            ]
            self.goals[handle.id] = handle
            excess = len(self.goals) - self.keep_goals
            if excess > 0:  # forget the oldest finished goals (running ones stay, however old)
                for old in [i for i, g in self.goals.items() if g.status in TERMINAL][:excess]:
                    del self.goals[old]
        if busy:
            handle.set_status(GoalStatus.REJECTED, f"{action.name} is busy with goal {busy[0].id}; cancel it first")
            return handle
        reason = action.precondition(self.lab, goal) if action.precondition else None
        if reason:
            handle.set_status(GoalStatus.REJECTED, reason)
            return handle
        threading.Thread(target=self._run, args=(handle,), name=f"action{action.name}", daemon=True).start()
        return handle

    def cancel(self, handle: GoalHandle) -> None:
        with handle._changed:
            if handle.status == GoalStatus.PENDING:
                handle.status = GoalStatus.PREEMPTED
                handle.message = "canceled before it started"
            elif handle.status == GoalStatus.ACTIVE:
                handle.status = GoalStatus.PREEMPTING
            handle.notify()

    def _run(self, handle: GoalHandle) -> None:
        with handle._changed:
            if handle.status != GoalStatus.PENDING:
                return
            handle.status = GoalStatus.ACTIVE
            handle.notify()
        try:
            result = handle.action.execute(self.lab, handle.goal, handle)
        except GoalFailure as failure:
            handle.set_status(GoalStatus.ABORTED, str(failure))
            return
        except GoalPreempted as preempted:
            handle.set_status(GoalStatus.PREEMPTED, str(preempted), preempted.result.model_dump(by_alias=True))
            return
        except GoalSucceeded as succeeded:
            handle.set_status(GoalStatus.SUCCEEDED, "done", succeeded.result.model_dump(by_alias=True))
            return
        except Exception as exc:  # noqa: BLE001 - an aborted goal, the server goes on
            reason = "".join(traceback.format_exception_only(exc)).strip()
            handle.set_status(GoalStatus.ABORTED, reason)
            return
        final = GoalStatus.PREEMPTED if handle.cancel_requested else GoalStatus.SUCCEEDED
        handle.set_status(
            final, "canceled" if final == GoalStatus.PREEMPTED else "done", result.model_dump(by_alias=True)
        )
