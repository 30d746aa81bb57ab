"""The action provider's ops (rosbridge_suite's ROS 2 action family): advertise_action /
unadvertise_action, and the provider's answers to the goals the lab sends it, action_feedback and
action_result (app/ros/node_actions.py has the goal's life)."""

from __future__ import annotations

from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id
from app.rosbridge.protocol import BadFrame, field, name_field


class AdvertiseAction(Capability):
    """The actions this client provides (in the lab's ActionServer while it is connected: the
    registry of node actions holds them, and their goals)."""

    async def advertise_action(self, message: dict, id_: Id) -> None:
        name = name_field(message, "action")
        type_name = field(message, "type", str)
        try:
            self.bridge.actions.advertise(name, type_name, self.session)
        except ValueError as refused:
            raise BadFrame(f"advertise_action: {refused}") from None
        await self.session.report(
            "info", f"advertise_action: {name} [{type_name}] is provided by {self.session.name}", id_
        )

    async def unadvertise_action(self, message: dict, id_: Id) -> None:
        name = name_field(message, "action")
        if not self.bridge.actions.unadvertise(name, self.session):
            await self.session.report("warning", f"unadvertise_action: {name} is not provided by this client", id_)

    async def action_feedback(self, message: dict, id_: Id) -> None:
        name = name_field(message, "action")
        values = field(message, "values", dict, {})
        try:
            self.bridge.actions.feedback(self.session, message.get("id"), name, values)
        except ValueError as refused:
            raise BadFrame(f"action_feedback: {refused}") from None

    async def action_result(self, message: dict, id_: Id) -> None:
        name = name_field(message, "action")
        ok = field(message, "result", bool)
        status = field(message, "status", int, 4 if ok else 6)
        values = message.get("values")
        try:
            self.bridge.actions.result(self.session, message.get("id"), name, values, status, ok)
        except ValueError as refused:
            raise BadFrame(f"action_result: {refused}") from None

    def finish(self) -> None:
        self.bridge.actions.drop(self.session)  # its actions go, their goals abort


OPS: Ops = {
    "advertise_action": Op(AdvertiseAction, AdvertiseAction.advertise_action, mutating=True),
    "unadvertise_action": Op(AdvertiseAction, AdvertiseAction.unadvertise_action, mutating=True),
    "action_feedback": Op(AdvertiseAction, AdvertiseAction.action_feedback, mutating=True),
    "action_result": Op(AdvertiseAction, AdvertiseAction.action_result, mutating=True),
}
