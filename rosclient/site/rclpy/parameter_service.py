"""rclpy.parameter_service.ParameterService: a node's parameters served with the standard
rcl_interfaces services /<node>/get_parameters, set_parameters, set_parameters_atomically,
list_parameters, describe_parameters and get_parameter_types (they run inside spin, like every
callback), so `hri-lab param set /node name value` reaches the running node."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from rclpy.exceptions import RCLError
from rclpy.parameter import Parameter, from_value_msg

if TYPE_CHECKING:
    from rclpy.node import Node

SERVICES = {  # service suffix -> rcl_interfaces type
    "describe_parameters": "DescribeParameters",
    "get_parameters": "GetParameters",
    "get_parameter_types": "GetParameterTypes",
    "list_parameters": "ListParameters",
    "set_parameters": "SetParameters",
    "set_parameters_atomically": "SetParametersAtomically",
}


class ParameterService:
    def __init__(self, node: Node) -> None:
        from rcl_interfaces import srv

        self._node = node
        self.services = []
        for suffix, type_name in SERVICES.items():
            try:
                self.services.append(node.create_service(getattr(srv, type_name), f"~/{suffix}", getattr(self, suffix)))
            except RCLError as refused:  # another node of this name serves them: ROS 2 warns, the node runs on
                node.get_logger().warning(
                    f"{refused}: a node named {node.get_fully_qualified_name()} runs already; this one's "
                    f"parameters are not served"
                )
                break

    def get_parameters(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import ParameterValue

        response.values = [self._node._parameters[n].get_parameter_value() if n in self._node._parameters else ParameterValue()
                           for n in request.names]
        return response

    def get_parameter_types(self, request: Any, response: Any) -> Any:
        response.types = bytes(self._node._parameters[n].type_.value if n in self._node._parameters else 0 for n in request.names)
        return response

    def set_parameters(self, request: Any, response: Any) -> Any:
        response.results = [self._node._set([Parameter(p.name, Parameter.Type(p.value.type), from_value_msg(p.value))])
                            for p in request.parameters]
        return response

    def set_parameters_atomically(self, request: Any, response: Any) -> Any:
        response.result = self._node._set([Parameter(p.name, Parameter.Type(p.value.type), from_value_msg(p.value))
                                     for p in request.parameters])
        return response

    def list_parameters(self, request: Any, response: Any) -> Any:
        names = sorted(self._node._parameters)
        if request.prefixes:
            names = [n for n in names if any(n == p or n.startswith(p + ".") for p in request.prefixes)]
        if request.depth:
            names = [n for n in names if n.count(".") < request.depth]
        response.result.names = names
        response.result.prefixes = sorted({n.rsplit(".", 1)[0] for n in names if "." in n})
        return response

    def describe_parameters(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import ParameterDescriptor

        response.descriptors = [self._node._descriptors.get(n, ParameterDescriptor(name=n)) for n in request.names]
        return response
