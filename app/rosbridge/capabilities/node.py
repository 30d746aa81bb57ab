"""node: a client names the ROS node (or nodes) it runs, e.g. `{"op": "node", "name": "/talker"}`,
as `hri-lab run`'s rospy and rclpy do when a program calls init_node or makes a Node. rosbridge_suite
has no such op (its clients are one node, /rosbridge_websocket); here a program is its own node,
and its name is what errors, rosapi (`/rosapi/nodes`, `node_details`), `GET /services/NAME`,
/rosout and the dashboard show. A client that names none is `/rosbridge_client_N`."""

from __future__ import annotations

import re

from app.ros.names import LAB_NODE
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id
from app.rosbridge.protocol import BadFrame, name_field

MAX_NODES = 64  # names one connection may declare
_NODE_NAME = re.compile(r"^(/[A-Za-z_][A-Za-z0-9_]*)+$")  # ROS: namespaces, then the base name


class Node(Capability):
    """The nodes the client runs (session.node_names: its name in errors, rosapi and the lab)."""

    async def node(self, message: dict, id_: Id) -> None:
        name = name_field(message, "name")
        if not _NODE_NAME.match(name):
            raise BadFrame(
                f"node: field 'name' must be a ROS node name (letters, digits, '_', namespaces by '/'), got {name[:80]!r}"
            )
        if name == LAB_NODE:
            raise BadFrame(f"node: {name} is the lab's own node")
        names = self.session.node_names
        if name in names:
            return
        if len(names) >= MAX_NODES:
            raise BadFrame(f"node: a connection names at most {MAX_NODES} nodes")
        names.append(name)


OPS: Ops = {"node": Op(Node, Node.node)}
