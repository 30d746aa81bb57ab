"""Actions as actionlib has them: goal / feedback / result / cancel, with the goal states
pending, active, preempting, succeeded, aborted, preempted, rejected.

One declaration per action (name, type, goal/result/feedback models, execute). Each action serves
one goal at a time: a goal sent while another is pending or active is REJECTED (the caller
cancels the running one first). A goal runs in its own thread; `execute(lab, goal, handle)`
publishes feedback with `handle.feedback(...)`, checks `handle.cancel_requested` (or sleeps
with `handle.wait(s)`, which wakes on cancel) and returns the result. Returning while a cancel
is requested ends PREEMPTED; raising `GoalFailure` ends ABORTED with its message (any other
exception: ABORTED with its type and message); returning ends SUCCEEDED. An action may declare
`precondition(lab, goal) -> reason or None`: a goal that cannot run now is REJECTED up front (409).

REST: POST /actions/{name}/goals (typed goal) -> goal id and status; GET .../goals/{id}
(long-poll with ?after=N&wait=S for feedback beyond the N-th); POST .../goals/{id}/cancel;
WebSocket .../goals/{id}/stream (every feedback and the final state).
"""
import asyncio
import threading
import time
import traceback
import uuid
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, Callable

from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect
from fastapi.responses import JSONResponse

from app.ros.messages import RosMessage, definition
from app.api.typed_routes import with_body


class GoalFailure(Exception):
    """A goal that could not be done (the reason is the message, shown as it is)."""


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
    goal: type[RosMessage]
    result: type[RosMessage]
    feedback: type[RosMessage]
    execute: Callable[[Any, Any, "GoalHandle"], RosMessage]
    description: str = ""
    precondition: Callable[[Any, Any], str | None] | None = None  # (lab, goal) -> why it cannot run now

    @property
    def definition(self) -> str:
        """The .action text: goal --- result --- feedback."""
        return "\n".join(part for part in (definition(self.goal), "---", definition(self.result), "---", definition(self.feedback)) if part)


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

    @property
    def cancel_requested(self) -> bool:
        return self.status == GoalStatus.PREEMPTING

    def feedback(self, message: RosMessage) -> None:
        with self._changed:
            self.feedbacks.append(message.model_dump(by_alias=True))
            self._changed.notify_all()

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
            self._changed.notify_all()

    def wait_for_update(self, after: int, timeout: float) -> None:
        """Block until there is feedback beyond `after`, a terminal state, or timeout."""
        end = time.monotonic() + timeout
        with self._changed:
            while len(self.feedbacks) <= after and self.status not in TERMINAL:
                left = end - time.monotonic()
                if left <= 0:
                    return
                self._changed.wait(left)

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

    def __init__(self, actions: list[Action], lab: Any) -> None:
        self.actions = {a.name: a for a in actions}
        self.lab = lab
        self.goals: dict[str, GoalHandle] = {}
        self._lock = threading.Lock()

    def get(self, name: str) -> Action | None:
        return self.actions.get("/" + name.lstrip("/"))

    def send_goal(self, action: Action, goal: RosMessage) -> GoalHandle:
        handle = GoalHandle(action, goal)
        with self._lock:
            busy = [g for g in self.goals.values() if g.action is action and g.status not in TERMINAL]
            self.goals[handle.id] = handle
            while len(self.goals) > self.keep_goals:
                oldest = next(iter(self.goals))
                if self.goals[oldest].status not in TERMINAL:
                    break
                del self.goals[oldest]
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
            handle._changed.notify_all()

    def _run(self, handle: GoalHandle) -> None:
        with handle._changed:
            if handle.status != GoalStatus.PENDING:
                return
            handle.status = GoalStatus.ACTIVE
            handle._changed.notify_all()
        try:
            result = handle.action.execute(self.lab, handle.goal, handle)
        except GoalFailure as failure:
            handle.set_status(GoalStatus.ABORTED, str(failure))
            return
        except Exception as exc:  # noqa: BLE001 - an aborted goal, the server goes on
            reason = "".join(traceback.format_exception_only(exc)).strip()
            handle.set_status(GoalStatus.ABORTED, reason)
            return
        final = GoalStatus.PREEMPTED if handle.cancel_requested else GoalStatus.SUCCEEDED
        handle.set_status(final, "canceled" if final == GoalStatus.PREEMPTED else "done", result.model_dump(by_alias=True))

    # --- HTTP -------------------------------------------------------------------------------
    def router(self) -> APIRouter:
        r = APIRouter(tags=["actions"])

        def goal_of(name: str, goal_id: str) -> GoalHandle:
            handle = self.goals.get(goal_id)
            if handle is None or handle.action.name != "/" + name.lstrip("/"):
                raise HTTPException(404, f"no goal {goal_id} of action /{name.lstrip('/')}")
            return handle

        @r.get("/actions", summary="Actions with their types (ros2 action list -t)")
        def list_actions() -> list[dict]:
            return [{"name": a.name, "type": a.type} for a in self.actions.values()]

        for action in self.actions.values():
            r.add_api_route(
                f"/actions{action.name}/goals",
                with_body(action.goal, lambda goal, a=action: self._accept(a, goal), "send_goal" + action.name.replace("/", "_")),
                methods=["POST"], status_code=202, summary=f"send a goal to {action.name} ({action.type})",
                description=f"{action.description}\n\n```\n{action.definition}\n```",
            )

        @r.get("/actions/{name}", summary="Type and .action definition of an action")
        def action_info(name: str) -> dict:
            action = self.get(name)
            if action is None:
                raise HTTPException(404, f"action '/{name.lstrip('/')}' does not exist")
            return {"name": action.name, "type": action.type, "definition": action.definition,
                    "description": action.description, "goal_schema": action.goal.model_json_schema(by_alias=True)}

        @r.get("/actions/{name}/goals/{goal_id}", summary="Status, feedback and result of a goal (long-poll)")
        def goal_status(name: str, goal_id: str, after: int = Query(0, ge=0), wait: float = Query(0.0, ge=0.0, le=30.0)) -> dict:
            handle = goal_of(name, goal_id)
            if wait > 0:
                handle.wait_for_update(after, wait)
            return handle.view(after)

        @r.post("/actions/{name}/goals/{goal_id}/cancel", summary="Cancel a goal")
        def cancel(name: str, goal_id: str) -> dict:
            handle = goal_of(name, goal_id)
            self.cancel(handle)
            return handle.view(len(handle.feedbacks))

        @r.websocket("/actions/{name}/goals/{goal_id}/stream")
        async def stream(websocket: WebSocket, name: str, goal_id: str) -> None:
            handle = self.goals.get(goal_id)
            if handle is None or handle.action.name != "/" + name.lstrip("/"):
                await websocket.close(code=1008, reason="no such goal")
                return
            await websocket.accept()
            sent = 0
            try:
                while True:
                    await asyncio.to_thread(handle.wait_for_update, sent, 0.5)
                    view = handle.view(sent)
                    for fb in view["feedback"]:
                        await websocket.send_json({"feedback": fb})
                    sent = view["feedback_count"]
                    if handle.status in TERMINAL:
                        await websocket.send_json({"status": view["status"], "result": view["result"], "message": view["message"]})
                        await websocket.close()
                        return
            except (WebSocketDisconnect, RuntimeError):
                return

        return r

    def _accept(self, action: Action, goal: RosMessage) -> JSONResponse:
        handle = self.send_goal(action, goal)
        return JSONResponse(handle.view(), status_code=202 if handle.status != GoalStatus.REJECTED else 409)
