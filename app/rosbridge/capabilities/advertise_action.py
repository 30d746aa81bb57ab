"""The action provider's ops (rosbridge_suite's ROS 2 action family): advertise_action /
unadvertise_action, and the provider's answers to the goals the lab sends it, action_feedback and
action_result (app/rosbridge/internal/node_actions.py has the goal's life)."""

from __future__ import annotations

from typing import Any

from app.rosbridge.capabilities.op import Op
from app.rosbridge.protocol import BadFrame, field, name_field


async def advertise_action(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "action")
    type_name = field(message, "type", str)
    try:
        session.bridge.node_actions.advertise(name, type_name, session)
    except ValueError as refused:
        raise BadFrame(f"advertise_action: {refused}") from None
    await session.report("info", f"advertise_action: {name} [{type_name}] is provided by {session.name}", id_)


async def unadvertise_action(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "action")
    if not session.bridge.node_actions.unadvertise(name, session):
        await session.report("warning", f"unadvertise_action: {name} is not provided by this client", id_)


async def action_feedback(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "action")
    values = field(message, "values", dict, {})
    try:
        session.bridge.node_actions.feedback(session, message.get("id"), name, values)
    except ValueError as refused:
        raise BadFrame(f"action_feedback: {refused}") from None


async def action_result(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "action")
    ok = field(message, "result", bool)
    status = field(message, "status", int, 4 if ok else 6)
    values = message.get("values")
    try:
        session.bridge.node_actions.result(session, message.get("id"), name, values, status, ok)
    except ValueError as refused:
        raise BadFrame(f"action_result: {refused}") from None


OPS = {
    "advertise_action": Op(advertise_action, mutating=True),
    "unadvertise_action": Op(unadvertise_action, mutating=True),
    "action_feedback": Op(action_feedback, mutating=True),
    "action_result": Op(action_result, mutating=True),
}
