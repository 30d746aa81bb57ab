"""rosapi: the services rosbridge clients use to look around (roslibpy's get_topics, get_param,
Foxglove's topics_and_raw_types, ...), answered from the lab's own registries. Parameter names are
rosapi's `/node:name`; values travel as JSON text, as rosapi has them."""
from __future__ import annotations

import json
from typing import Any

from app.ros.messages import RosType
from app.ros.params import ParameterRefused
from app.ros.services import ServiceFailure
from app.lab.topics import TOPICS

LAB_NODE = "/hri_lab"
READ_ONLY = {"/rosapi/topics", "/rosapi/topic_type", "/rosapi/topics_for_type", "/rosapi/services", "/rosapi/service_type",
             "/rosapi/services_for_type", "/rosapi/service_request_details", "/rosapi/service_response_details",
             "/rosapi/message_details", "/rosapi/nodes", "/rosapi/node_details", "/rosapi/get_param_names",
             "/rosapi/get_param", "/rosapi/has_param", "/rosapi/get_time", "/rosapi/topics_and_raw_types",
             "/rosapi/action_servers"}
WRITING = {"/rosapi/set_param"}
NAMES = READ_ONLY | WRITING

# nested message types of the lab's topics, by field name (ROS's own spellings)
NESTED = {"header": "std_msgs/Header", "stamp": "builtin_interfaces/Time", "wrench": "geometry_msgs/Wrench",
          "force": "geometry_msgs/Vector3", "torque": "geometry_msgs/Vector3", "linear": "geometry_msgs/Vector3",
          "angular": "geometry_msgs/Vector3", "pose": "geometry_msgs/Pose", "position": "geometry_msgs/Point",
          "orientation": "geometry_msgs/Quaternion", "tangential_force": "geometry_msgs/Vector3",
          "centre_of_pressure": "hri_lab/Point2"}


def _scalar(value: Any) -> str:
    return {bool: "bool", int: "int32", float: "float64", str: "string"}.get(type(value), "string")


def message_typedefs(type_name: str, sample: dict) -> list[dict]:
    """rosapi TypeDefs of a message, its nested types after it (inferred from a sample message)."""
    out: list[dict] = []
    seen: set[str] = set()

    def visit(name: str, message: dict) -> None:
        if name in seen:
            return
        seen.add(name)
        typedef = {"type": name, "fieldnames": [], "fieldtypes": [], "fieldarraylen": [], "examples": [],
                   "constnames": [], "constvalues": []}
        out.append(typedef)
        nested = []
        for key, value in message.items():
            array = isinstance(value, list)
            item = (value[0] if value else 0.0) if array else value
            kind = NESTED.get(key, f"{name}_{key}") if isinstance(item, dict) else _scalar(item)
            if isinstance(item, dict):
                nested.append((kind, item))
            typedef["fieldnames"].append(key)
            typedef["fieldtypes"].append(kind)
            typedef["fieldarraylen"].append(0 if array else -1)
            typedef["examples"].append("{}" if isinstance(item, dict) else ("[]" if array else json.dumps(item)))
        for kind, item in nested:
            visit(kind, item)

    visit(type_name, sample)
    return out


def full_text(typedefs: list[dict]) -> str:
    """The .msg text with its nested definitions (the format of bag files and Foxglove)."""
    parts = []
    for i, typedef in enumerate(typedefs):
        lines = [f"{t}{'[]' if n == 0 else ''} {f}" for f, t, n in
                 zip(typedef["fieldnames"], typedef["fieldtypes"], typedef["fieldarraylen"])]
        head = "" if i == 0 else "=" * 80 + f"\nMSG: {typedef['type']}\n"
        parts.append(head + "\n".join(lines))
    return "\n".join(parts)


def model_typedefs(type_name: str, model) -> list[dict]:
    """TypeDefs of a request/response model from its ROS field types."""
    typedef = {"type": type_name, "fieldnames": [], "fieldtypes": [], "fieldarraylen": [], "examples": [],
               "constnames": [], "constvalues": []}
    for name, info in model.model_fields.items():
        ros = next((m for m in info.metadata if isinstance(m, RosType)), RosType("string"))
        array = ros.name.endswith("[]")
        typedef["fieldnames"].append(info.alias or name)
        typedef["fieldtypes"].append(ros.name.removesuffix("[]"))
        typedef["fieldarraylen"].append(0 if array else -1)
        typedef["examples"].append("[]" if array else "")
    return [typedef]


def _param_name(name: str) -> tuple[str, str]:
    node, sep, param = name.partition(":")
    if not sep or not param:
        raise ServiceFailure(f"Malformed parameter name: {name}; expecting <node_name>:<param_name>")
    return node.strip("/"), param


def call(bridge, session, name: str, args: dict) -> dict:
    """Answer a rosapi service (runs in a worker thread: parameters ask the simulation)."""
    lab = bridge.lab
    if name == "/rosapi/topics":
        topics = bridge.topic_types()
        return {"topics": list(topics), "types": list(topics.values())}
    if name == "/rosapi/topics_for_type":
        return {"topics": [t for t, ty in bridge.topic_types().items() if ty == args.get("type")]}
    if name == "/rosapi/topic_type":
        return {"type": bridge.topic_types().get("/" + str(args.get("topic", "")).strip("/"), "")}
    if name == "/rosapi/services":
        return {"services": [s.name for s in bridge.services] + sorted(NAMES)}
    if name == "/rosapi/services_for_type":
        return {"services": [s.name for s in bridge.services if s.type == args.get("type")]}
    if name == "/rosapi/service_type":
        service = bridge.services.get(str(args.get("service", "")))
        return {"type": service.type if service else ""}
    if name in ("/rosapi/service_request_details", "/rosapi/service_response_details"):
        wanted = str(args.get("type", ""))
        service = next((s for s in bridge.services if s.type == wanted), None)
        if service is None:
            return {"typedefs": []}
        part = "request" if name.endswith("request_details") else "response"
        return {"typedefs": model_typedefs(f"{wanted}_{part.capitalize()}", getattr(service, part))}
    if name == "/rosapi/message_details":
        wanted = str(args.get("type", ""))
        snapshot = lab.snapshot()
        topic = next((t for t in TOPICS if t.type == wanted), None)
        if topic is not None:
            return {"typedefs": message_typedefs(wanted, topic.build(snapshot))}
        for typedefs in (message_typedefs(t.type, t.build(snapshot)) for t in TOPICS):
            nested = next((d for d in typedefs if d["type"] == wanted), None)
            if nested is not None:
                return {"typedefs": [nested]}
        return {"typedefs": []}
    if name == "/rosapi/topics_and_raw_types":
        snapshot = lab.snapshot()
        texts = {t.name: full_text(message_typedefs(t.type, t.build(snapshot))) for t in TOPICS}
        topics = bridge.topic_types()
        return {"topics": list(topics), "types": list(topics.values()),
                "typedefs_full_text": [texts.get(t, "") for t in topics]}
    if name == "/rosapi/nodes":
        return {"nodes": [LAB_NODE] + [s.name for s in bridge.sessions]}
    if name == "/rosapi/node_details":
        node = str(args.get("node", ""))
        if node == LAB_NODE:
            return {"subscribing": ["/cartesian_velocity_controller/command"], "publishing": [t.name for t in TOPICS],
                    "services": [s.name for s in bridge.services if bridge.nodes.provided_by(s.name) is None]}
        other = next((s for s in bridge.sessions if s.name == node), None)
        if other is None:
            return {"subscribing": [], "publishing": [], "services": []}
        return other.details()
    if name == "/rosapi/action_servers":
        return {"action_servers": list(bridge.actions.actions)}
    if name == "/rosapi/get_param_names":
        return {"names": [f"/{p.node}:{p.name}" for p in lab.params.declarations.values()]}
    if name == "/rosapi/has_param":
        node, param = _param_name(str(args.get("name", "")))
        return {"exists": (node, param) in lab.params.declarations}
    if name == "/rosapi/get_param":
        node, param = _param_name(str(args.get("name", "")))
        try:
            return {"value": json.dumps(lab.params.get(node, param))}
        except ParameterRefused:
            default = args.get("default_value", "")
            if default:
                return {"value": default}
            raise ServiceFailure(f"parameter {node}:{param} is not declared") from None
    if name == "/rosapi/set_param":
        node, param = _param_name(str(args.get("name", "")))
        try:
            value = json.loads(args.get("value", ""))
        except (TypeError, ValueError):
            raise ServiceFailure("set_param: 'value' must be JSON text, e.g. \"0.6\" or \"\\\"patch\\\"\"") from None
        try:
            lab.params.set(node, param, value)
        except ParameterRefused as refused:
            raise ServiceFailure(str(refused)) from None
        return {}
    if name == "/rosapi/get_time":
        time = lab.snapshot().time
        sec = int(time)
        nanosec = int(round((time - sec) * 1e9))
        # ROS 2 builtin_interfaces/Time (sec, nanosec); roslibpy's get_time reads ROS 1's secs/nsecs
        return {"time": {"sec": sec, "nanosec": nanosec, "secs": sec, "nsecs": nanosec}}
    raise ServiceFailure(f"service {name} does not exist")
