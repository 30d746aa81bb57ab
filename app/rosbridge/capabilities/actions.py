"""send_action_goal (feedback when asked) / cancel_action_goal on the lab's ActionServer, answered
with action_feedback and action_result (status as action_msgs/GoalStatus), as rosbridge_suite's
ROS 2 action ops."""

from __future__ import annotations

import asyncio
import json

from app.ros.actions import TERMINAL, GoalHandle, GoalStatus
from app.ros.messages import BadArguments, message_from_args
from app.rosbridge.capabilities.call_service import MAX_CALLS_IN_FLIGHT
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import BadFrame, field, name_field

# actionlib's end states as action_msgs/GoalStatus codes (4 succeeded, 5 canceled, 6 aborted)
GOAL_STATUS = {GoalStatus.SUCCEEDED: 4, GoalStatus.PREEMPTED: 5, GoalStatus.ABORTED: 6, GoalStatus.REJECTED: 6}


class Actions(Capability):
    """The goals this client sent, by its ids: they stop when it goes."""

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.goals: dict[Id | str, GoalHandle] = {}  # the goal's id (the op's, else the handle's) -> handle

    async def send_action_goal(self, message: dict, id_: Id) -> None:
        session, actions = self.session, self.bridge.actions
        name = name_field(message, "action")
        args = field(message, "args", (dict, list), {})
        feedback = field(message, "feedback", bool, False)
        action = actions.get(name)
        if action is None:
            await self._result(name, id_, 6, False, f"action {name} does not exist")
            raise BadFrame(f"send_action_goal: action {name} does not exist")
        try:
            goal = message_from_args(action.goal, args, "goal")
        except BadArguments as bad:
            await self._result(name, id_, 6, False, str(bad))
            raise BadFrame(f"send_action_goal {name}: {bad}") from None
        if session.in_flight >= MAX_CALLS_IN_FLIGHT:
            raise BadFrame(f"send_action_goal: {MAX_CALLS_IN_FLIGHT} calls of this client are already in flight")
        handle = actions.send_goal(action, goal)
        self.goals[id_ if id_ is not None else handle.id] = handle
        session.in_flight += 1
        session.spawn(self._follow(name, id_, handle, feedback))

    async def _follow(self, name: str, id_: Id, handle: GoalHandle, feedback: bool) -> None:
        """action_feedback as it comes (when asked), then action_result."""
        sent = 0
        try:
            while True:
                view = handle.view(sent)
                if feedback:
                    for values in view["feedback"]:
                        await self.session.send({"op": "action_feedback", "id": id_, "action": name, "values": values})
                sent = view["feedback_count"]
                if handle.status in TERMINAL:
                    break
                await asyncio.sleep(0.02)
        finally:
            self.session.in_flight -= 1
        view = handle.view(sent)
        status_ = GoalStatus(view["status"])
        values = view["result"] if view["result"] is not None else view["message"]
        await self._result(name, id_, GOAL_STATUS.get(status_, 0), status_ == GoalStatus.SUCCEEDED, values)

    async def _result(self, name: str, id_: Id, code: int, ok: bool, values: object) -> None:
        await self.session.send(
            {"op": "action_result", "id": id_, "action": name, "values": values, "status": code, "result": ok}
        )

    async def cancel_action_goal(self, message: dict, id_: Id) -> None:
        handle = self.goals.get(id_)
        if handle is None:
            raise BadFrame(f"cancel_action_goal: no goal with id {json.dumps(id_)[:80]} from this client")
        self.bridge.actions.cancel(handle)

    def finish(self) -> None:
        for handle in self.goals.values():  # the client is gone: its goals stop
            if handle.status not in TERMINAL:
                self.bridge.actions.cancel(handle)
        self.goals.clear()


OPS: Ops = {
    "send_action_goal": Op(Actions, Actions.send_action_goal, mutating=True),
    "cancel_action_goal": Op(Actions, Actions.cancel_action_goal, mutating=True),
}
