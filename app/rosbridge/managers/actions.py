"""Actions (rosbridge_suite's ROS 2 action ops): the lab's ActionServer, which the clients send goals
to, and the actions nodes provide in it (app/ros/node_actions.py) with their goals' feedback and
results."""

from __future__ import annotations

from typing import Any

from app.ros.actions import Action, ActionServer, GoalHandle
from app.ros.messages import RosMessage
from app.ros.names import LAB_NODE
from app.ros.node_actions import NodeActions
from app.ros.node_services import NodeClient


class ActionManager:
    def __init__(self, server: ActionServer, nodes: NodeActions) -> None:
        self.server = server  # every action: the lab's own and the nodes'
        self.nodes = nodes  # the actions nodes provide, in the same server

    # --- a client sends goals ---
    def get(self, name: str) -> Action | None:
        return self.server.get(name)

    def names(self) -> list[str]:
        """Every action a client may send a goal to (rosapi's action_servers)."""
        return list(self.server.actions)

    def server_node(self, name: str) -> str | None:
        """The node that serves action `name` (`ros2 action info`'s servers): the lab's for its own
        actions, the providing client's node for a node's; None when there is no such action."""
        if name not in self.server.actions:
            return None
        provider = self.nodes.providers.get(name)
        return provider.name if provider is not None else LAB_NODE

    def send_goal(self, action: Action, goal: RosMessage) -> GoalHandle:
        return self.server.send_goal(action, goal)

    def cancel(self, handle: GoalHandle) -> None:
        self.server.cancel(handle)

    # --- a client provides actions (ValueError with the reason of a refusal) ---
    def advertise(self, name: str, type_name: str, session: NodeClient) -> None:
        self.nodes.advertise(name, type_name, session)

    def unadvertise(self, name: str, session: NodeClient) -> bool:
        return self.nodes.unadvertise(name, session)

    def feedback(self, session: NodeClient, goal_id: object, name: str, values: Any) -> None:
        self.nodes.feedback(session, goal_id, name, values)

    def result(self, session: NodeClient, goal_id: object, name: str, values: Any, status: int, ok: bool) -> None:
        self.nodes.result(session, goal_id, name, values, status, ok)

    def drop(self, session: NodeClient) -> None:
        """`session`'s client is gone: its actions go, their goals abort."""
        self.nodes.drop(session)
