"""The parameters of a node that runs elsewhere, the ROS 2 way: the node (an rclpy program over
rosbridge) provides the standard parameter services, and the lab's parameter server
(app/ros/params.py, `remote`) reaches its parameters through them — for GET /params, `hri-lab
param list/get/set/describe/dump`, the page's parameter tab and rosapi. They go when the node does.

The services (rcl_interfaces/srv, standard fields), for node N:
- /N/list_parameters     {prefixes: [], depth: 0}    -> {result: {names: [...], prefixes: [...]}}
- /N/get_parameters      {names: [...]}              -> {values: [ParameterValue, ...]}
- /N/set_parameters      {parameters: [{name, value: ParameterValue}]}
                                                     -> {results: [{successful, reason}]}
- /N/describe_parameters {names: [...]}              -> {descriptors: [ParameterDescriptor, ...]}
ParameterValue is {type, bool_value, integer_value, double_value, string_value, *_array_value}
with rcl_interfaces/ParameterType's codes. A node is listed once it provides list_parameters
and get_parameters; set and describe are asked when used. A refused set reports the node's
SetParametersResult.reason as it is.
"""

from __future__ import annotations

import math
from typing import Any

from app.ros.node_services import NodeServices, OpenMessage
from app.ros.params import ParameterRefused, type_name
from app.ros.services import ServiceFailure

# rcl_interfaces/msg/ParameterType
NOT_SET, BOOL, INTEGER, DOUBLE, STRING = 0, 1, 2, 3, 4
BYTE_ARRAY, BOOL_ARRAY, INTEGER_ARRAY, DOUBLE_ARRAY, STRING_ARRAY = 5, 6, 7, 8, 9
FIELDS = {
    BOOL: "bool_value",
    INTEGER: "integer_value",
    DOUBLE: "double_value",
    STRING: "string_value",
    BYTE_ARRAY: "byte_array_value",
    BOOL_ARRAY: "bool_array_value",
    INTEGER_ARRAY: "integer_array_value",
    DOUBLE_ARRAY: "double_array_value",
    STRING_ARRAY: "string_array_value",
}
TYPE_NAMES = {
    NOT_SET: "not set",
    BOOL: "bool",
    INTEGER: "integer",
    DOUBLE: "double",
    STRING: "string",
    BYTE_ARRAY: "byte_array",
    BOOL_ARRAY: "bool_array",
    INTEGER_ARRAY: "integer_array",
    DOUBLE_ARRAY: "double_array",
    STRING_ARRAY: "string_array",
}
SERVICES = ("list_parameters", "get_parameters", "set_parameters", "describe_parameters")


def to_json(value: Any) -> Any:
    """rcl_interfaces/ParameterValue -> its JSON value (None: not set)."""
    if not isinstance(value, dict):
        return None
    kind = value.get("type", NOT_SET)
    return value.get(FIELDS[kind]) if kind in FIELDS else None


def from_json(value: Any, kind: int | None = None) -> dict:
    """A JSON value -> rcl_interfaces/ParameterValue; `kind`: the parameter's declared type (an
    integer is sent as a double to a double parameter: JSON has one number type); None: not set
    (`ros2 param delete`'s value)."""
    if value is None:
        return {"type": NOT_SET}
    if isinstance(value, bool):
        code = BOOL
    elif isinstance(value, int):
        code = DOUBLE if kind == DOUBLE else INTEGER
    elif isinstance(value, float):
        if not math.isfinite(value):
            raise ParameterRefused("a parameter value is a finite number")
        code = DOUBLE
    elif isinstance(value, str):
        code = STRING
    elif isinstance(value, list) and value and all(isinstance(x, type(value[0])) for x in value):
        first = value[0]
        code = {
            bool: BOOL_ARRAY,
            int: DOUBLE_ARRAY if kind == DOUBLE_ARRAY else INTEGER_ARRAY,
            float: DOUBLE_ARRAY,
            str: STRING_ARRAY,
        }.get(type(first), NOT_SET)
        if code == NOT_SET:
            raise ParameterRefused(
                f"a parameter array holds bools, integers, doubles or strings, not {type_name(first)}"
            )
    else:
        raise ParameterRefused(
            f"a parameter value is a bool, integer, double, string or an array of one of them, not {type_name(value)}"
        )
    if code == DOUBLE:
        value = float(value)
    elif code == DOUBLE_ARRAY:
        value = [float(x) for x in value]
    return {"type": code, FIELDS[code]: value}


class NodeParameters:
    """app/ros/params.py's RemoteParameters over the services nodes provide (NodeServices)."""

    def __init__(self, services: NodeServices) -> None:
        self.services = services

    def nodes(self) -> list[str]:
        provided = set(self.services.providers)
        out = []
        for name in provided:
            if name.endswith("/list_parameters"):
                node = name[: -len("/list_parameters")]
                if f"{node}/get_parameters" in provided:
                    out.append(node.strip("/"))
        return sorted(out)

    def _call(self, node: str, service: str, request: dict) -> dict:
        name = f"/{node}/{service}"
        if self.services.provided_by(name) is None:
            raise ParameterRefused(f"node /{node} does not provide {name}", 404)
        try:
            response = self.services.call(name, OpenMessage.model_validate(request))
        except ServiceFailure as failure:
            raise ParameterRefused(f"node /{node}: {failure}", failure.status) from None
        values = response.model_dump(by_alias=True)
        if not isinstance(values, dict):
            raise ParameterRefused(f"node /{node}: {service} answered {str(values)[:80]}", 502)
        return values

    def names(self, node: str) -> list[str]:
        result = self._call(node, "list_parameters", {"prefixes": [], "depth": 0}).get("result")
        names = result.get("names") if isinstance(result, dict) else None
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise ParameterRefused(f"node /{node}: list_parameters answered no result.names", 502)
        return names

    def get(self, node: str, names: list[str]) -> list[Any]:
        values = self._call(node, "get_parameters", {"names": names}).get("values")
        if not isinstance(values, list) or len(values) != len(names):
            raise ParameterRefused(
                f"node /{node}: get_parameters answered {len(values or [])} values for {len(names)} names", 502
            )
        return [to_json(v) for v in values]

    def _descriptor(self, node: str, name: str) -> dict:
        descriptors = self._call(node, "describe_parameters", {"names": [name]}).get("descriptors")
        if not isinstance(descriptors, list) or len(descriptors) != 1 or not isinstance(descriptors[0], dict):
            raise ParameterRefused(f"node /{node}: describe_parameters answered no descriptor for {name}", 502)
        return descriptors[0]

    def set(self, node: str, name: str, value: Any) -> None:
        kind = None
        if self.services.provided_by(f"/{node}/describe_parameters") is not None:
            kind = self._descriptor(node, name).get("type")
        results = self._call(
            node, "set_parameters", {"parameters": [{"name": name, "value": from_json(value, kind)}]}
        ).get("results")
        if not isinstance(results, list) or len(results) != 1 or not isinstance(results[0], dict):
            raise ParameterRefused(f"node /{node}: set_parameters answered no result", 502)
        if not results[0].get("successful", False):
            raise ParameterRefused(str(results[0].get("reason", "")) or "the node refused the value")

    def describe(self, node: str, name: str) -> dict:
        """The node's descriptor in Parameter.describe()'s shape (type, description, read_only,
        the range when the node declares one)."""
        descriptor = self._descriptor(node, name)
        out = {
            "node": node,
            "name": descriptor.get("name") or name,
            "type": TYPE_NAMES.get(descriptor.get("type", NOT_SET), str(descriptor.get("type"))),
            "description": descriptor.get("description", ""),
            "read_only": bool(descriptor.get("read_only", False)),
            "default": None,
        }
        if descriptor.get("additional_constraints"):
            out["additional_constraints"] = descriptor["additional_constraints"]
        for key in ("floating_point_range", "integer_range"):
            ranges = descriptor.get(key)
            if isinstance(ranges, list) and ranges and isinstance(ranges[0], dict):
                out["min_value"], out["max_value"] = ranges[0].get("from_value"), ranges[0].get("to_value")
        if out["type"] == "not set" or descriptor.get("type") is None:
            raise ParameterRefused("Parameter not set.", 404)
        return out
