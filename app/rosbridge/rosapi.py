"""rosapi: the services rosbridge clients use to look around (roslibpy's get_topics, get_param,
Foxglove's topics_and_raw_types, ...), answered from the lab's own registries. Parameter names are
rosapi's `/node:name` (ROS 2) or `/ns/name` (ROS 1's parameter server); values travel as JSON
text, as rosapi has them."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from app.ros import rosout
from app.ros.messages import RosType
from app.ros.names import LAB_NODE
from app.ros.param_tree import ParamError, canonical
from app.ros.params import ParameterRefused
from app.ros.services import ServiceFailure
from app.rosbridge.ports import BridgeLike
from app.rosbridge.protocol import ENDPOINT_KINDS

Handler = Callable[["BridgeLike", dict], dict]  # (the bridge, the request's fields) -> the response's values

# nested message types of the lab's topics, by field name (ROS's own spellings)
NESTED = {
    "header": "std_msgs/Header",
    "stamp": "builtin_interfaces/Time",
    "wrench": "geometry_msgs/Wrench",
    "force": "geometry_msgs/Vector3",
    "torque": "geometry_msgs/Vector3",
    "linear": "geometry_msgs/Vector3",
    "angular": "geometry_msgs/Vector3",
    "pose": "geometry_msgs/Pose",
    "position": "geometry_msgs/Point",
    "orientation": "geometry_msgs/Quaternion",
    "tangential_force": "geometry_msgs/Vector3",
    "centre_of_pressure": "hri_lab/Point2",
    "transforms": "geometry_msgs/TransformStamped",
    "transform": "geometry_msgs/Transform",
    "translation": "geometry_msgs/Vector3",
    "rotation": "geometry_msgs/Quaternion",
}


def _scalar(value: object) -> str:
    return {bool: "bool", int: "int32", float: "float64", str: "string"}.get(type(value), "string")


def _typedef(type_name: str) -> dict[str, Any]:
    """An empty rosapi TypeDef (rosapi_msgs/TypeDef): its fields are added by _add_field."""
    keys = ("fieldnames", "fieldtypes", "fieldarraylen", "examples", "constnames", "constvalues")
    return {"type": type_name} | {key: [] for key in keys}


def _add_field(typedef: dict[str, Any], name: str, type_name: str, array: bool, example: str) -> None:
    """One field: fieldarraylen 0 for an unbounded array, -1 for a single value."""
    typedef["fieldnames"].append(name)
    typedef["fieldtypes"].append(type_name)
    typedef["fieldarraylen"].append(0 if array else -1)
    typedef["examples"].append(example)


def message_typedefs(type_name: str, sample: dict) -> list[dict]:
    """rosapi TypeDefs of a message, its nested types after it (inferred from a sample message)."""
    out: list[dict] = []
    seen: set[str] = set()

    def visit(name: str, message: dict) -> None:
        if name in seen:
            return
        seen.add(name)
        typedef = _typedef(name)
        out.append(typedef)
        nested = []
        for key, value in message.items():
            array = isinstance(value, list)
            item = (value[0] if value else 0.0) if array else value
            kind = NESTED.get(key, f"{name}_{key}") if isinstance(item, dict) else _scalar(item)
            if isinstance(item, dict):
                nested.append((kind, item))
            example = "{}" if isinstance(item, dict) else ("[]" if array else json.dumps(item))
            _add_field(typedef, key, kind, array, example)
        for kind, item in nested:
            visit(kind, item)

    visit(type_name, sample)
    return out


def full_text(typedefs: list[dict]) -> str:
    """The .msg text with its nested definitions (the format of bag files and Foxglove)."""
    parts = []
    for i, typedef in enumerate(typedefs):
        lines = [
            f"{t}{'[]' if n == 0 else ''} {f}"
            for f, t, n in zip(typedef["fieldnames"], typedef["fieldtypes"], typedef["fieldarraylen"])
        ]
        head = "" if i == 0 else "=" * 80 + f"\nMSG: {typedef['type']}\n"
        parts.append(head + "\n".join(lines))
    return "\n".join(parts)


def model_typedefs(type_name: str, model) -> list[dict]:
    """TypeDefs of a request/response model from its ROS field types."""
    typedef = _typedef(type_name)
    for name, info in model.model_fields.items():
        ros = next((m for m in info.metadata if isinstance(m, RosType)), RosType("string"))
        array = ros.name.endswith("[]")
        _add_field(typedef, info.alias or name, ros.name.removesuffix("[]"), array, "[]" if array else "")
    return [typedef]


# --- parameters ------------------------------------------------------------------------------
# Two kinds of names, as rosapi has them: ROS 2's `/node:name` (a node's declared parameter, typed,
# with rclcpp's refusals) and ROS 1's `/ns/name` (the lab's ROS 1 parameter server, any name; a
# `/node/name` that a node declares is that declared parameter).


def _node_param(name: str) -> tuple[str, str] | None:
    """`/node:name` -> (node, name); None for a ROS 1 name."""
    node, sep, param = name.partition(":")
    if not sep:
        return None
    if not param or not node.strip("/"):
        raise ServiceFailure(f"Malformed parameter name: {name}; expecting <node_name>:<param_name>")
    return node.strip("/"), param


def _declared(lab, name: str) -> tuple[str, str] | None:
    """The declared parameter a ROS 1 name `/node/name` is, if any."""
    parts = canonical(name).strip("/").split("/")
    return (parts[0], parts[1]) if len(parts) == 2 and lab.params.has(parts[0], parts[1]) else None


def _json_arg(args: dict, key: str, what: str) -> Any:
    text = args.get(key, "")
    try:
        return json.loads(text)
    except (TypeError, ValueError):
        raise ServiceFailure(f'{what}: \'{key}\' must be JSON text, e.g. "0.6" or "\\"patch\\""') from None


def _get_param(lab, args: dict) -> dict:
    name = str(args.get("name", ""))
    default_text = args.get("default_value", args.get("default", ""))  # ROS 2's field, ROS 1's
    node_param = _node_param(name) or _declared(lab, name)
    if node_param is not None:
        try:
            return {"value": json.dumps(lab.params.get(*node_param))}
        except ParameterRefused as refused:
            if refused.status != 404:  # the node could not be asked
                raise ServiceFailure(str(refused)) from None
            if default_text:
                return {"value": default_text}
            raise ServiceFailure(f"parameter {node_param[0]}:{node_param[1]} is not declared") from None
    value = lab.param_tree.get(name, _UNSET)
    if value is _UNSET:
        node = canonical(name).strip("/")
        declared = {p.name: v for p, v in lab.params.items() if p.node == node}
        if declared:  # a node's namespace: its declared parameters
            return {"value": json.dumps(declared)}
        return {"value": default_text if default_text else "null"}  # ROS 1's rosapi: the default, else null
    return {"value": json.dumps(value)}


def _set_param(lab, args: dict) -> dict:
    name = str(args.get("name", ""))
    value = _json_arg(args, "value", "set_param")
    node_param = _node_param(name) or _declared(lab, name)
    if node_param is not None:
        try:
            lab.params.set(*node_param, value)
        except ParameterRefused as refused:
            raise ServiceFailure(str(refused)) from None
        return {}
    lab.param_tree.set(name, value)
    return {}


def _delete_param(lab, args: dict) -> dict:
    name = str(args.get("name", ""))
    node_param = _node_param(name) or _declared(lab, name)
    if node_param is not None:
        raise ServiceFailure(
            f"parameter {node_param[0]}:{node_param[1]} is declared by its node: it can be set, not deleted"
        )
    lab.param_tree.delete(name)  # deleting a name that is not set is no error (rosapi's)
    return {}


def _has_param(lab, args: dict) -> dict:
    name = str(args.get("name", ""))
    node_param = _node_param(name) or _declared(lab, name)
    if node_param is not None:
        return {"exists": lab.params.has(*node_param)}
    return {"exists": lab.param_tree.has(name)}


def _get_param_names(lab, args: dict) -> dict:
    return {"names": [f"/{node}:{name}" for node, name in lab.params.names()] + lab.param_tree.names()}


def _search_param(lab, args: dict) -> dict:
    found = lab.param_tree.search(str(args.get("name", "")))
    return {"global_name": found or ""}


_UNSET = object()


def lab_topics(bridge: BridgeLike) -> list:
    """The topics the lab's world publishes (app/worlds/contract.py), even while bags replay."""
    return bridge.topics.world_topics


def _samples(bridge: BridgeLike, snapshot: Any) -> dict[str, tuple[str, dict]]:
    """topic -> (type, a message of it): the lab's topics from the snapshot, /rosout a line."""
    samples = {t.name: (t.type, t.build(snapshot)) for t in lab_topics(bridge)}
    samples[rosout.TOPIC] = (rosout.TYPE, rosout.LogLine(0.0, "INFO", "", "").message())
    return samples


# --- the services, one handler each: (bridge, args) -> the response's values --------------------


def _topics(bridge: BridgeLike, args: dict) -> dict:
    topics = bridge.topics.types()
    return {"topics": list(topics), "types": list(topics.values())}


def _topics_for_type(bridge: BridgeLike, args: dict) -> dict:
    return {"topics": [t for t, ty in bridge.topics.types().items() if ty == args.get("type")]}


def _topic_type(bridge: BridgeLike, args: dict) -> dict:
    return {"type": bridge.topics.types().get("/" + str(args.get("topic", "")).strip("/"), "")}


def _services(bridge: BridgeLike, args: dict) -> dict:
    return {"services": bridge.services.names()}


def _services_for_type(bridge: BridgeLike, args: dict) -> dict:
    return {
        "services": [
            s.name for s in bridge.services.registry() if s.type == args.get("type") and bridge.services.offered(s.name)
        ]
    }


def _service_type(bridge: BridgeLike, args: dict) -> dict:
    entry = bridge.services.get(str(args.get("service", "")))
    return {"type": entry.type if entry is not None else ""}


def _details(part: str) -> Handler:
    """service_request_details / service_response_details: the TypeDefs of a service type's part."""

    def details(bridge: BridgeLike, args: dict) -> dict:
        wanted = str(args.get("type", ""))
        service = next((s for s in bridge.services.registry() if s.type == wanted), None)
        if service is None:
            return {"typedefs": []}
        return {"typedefs": model_typedefs(f"{wanted}_{part.capitalize()}", getattr(service, part))}

    return details


def _message_details(bridge: BridgeLike, args: dict) -> dict:
    wanted = str(args.get("type", ""))
    samples = _samples(bridge, bridge.lab.snapshot())
    sample = next((m for t, m in samples.values() if t == wanted), None)
    if sample is not None:
        return {"typedefs": message_typedefs(wanted, sample)}
    for typedefs in (message_typedefs(t, m) for t, m in samples.values()):
        nested = next((d for d in typedefs if d["type"] == wanted), None)
        if nested is not None:
            return {"typedefs": [nested]}
    return {"typedefs": []}


def _topics_and_raw_types(bridge: BridgeLike, args: dict) -> dict:
    samples = _samples(bridge, bridge.lab.snapshot())
    texts = {topic: full_text(message_typedefs(t, m)) for topic, (t, m) in samples.items()}
    topics = bridge.topics.types()
    # a node topic: the full text its publisher carried (hri-lab's programs do), not a lab sample's
    texts.update(bridge.topics.definitions())
    return {
        "topics": list(topics),
        "types": list(topics.values()),
        "typedefs_full_text": [texts.get(t, "") for t in topics],
    }


def _topic_arg(args: dict) -> str:
    return "/" + str(args.get("topic", "")).strip("/")


def _publishers(bridge: BridgeLike, args: dict) -> dict:
    """The nodes on a topic, as rosapi names them: the lab's node for its own topics, then clients."""
    topic = _topic_arg(args)
    lab = [LAB_NODE] if bridge.topics.lab_publishes(topic) else []
    return {"publishers": lab + [s.name for s in bridge.sessions.all() if topic in s.details()["publishing"]]}


def _subscribers(bridge: BridgeLike, args: dict) -> dict:
    topic = _topic_arg(args)
    # the lab's own: the command topic it follows (a teleop node waiting for a subscriber to /cmd_vel counts
    # it, as rospy's get_num_connections counts every subscriber), tf2_web_republisher's goal and cancel
    lab = [LAB_NODE] if topic == bridge.topics.command_topic or topic in bridge.tf.inputs else []
    return {"subscribers": lab + [s.name for s in bridge.sessions.all() if topic in s.details()["subscribing"]]}


LISTED_KINDS = (*ENDPOINT_KINDS, "action_server")  # /rosapi/endpoints' kinds: the told ones and the action servers


def _endpoints(bridge: BridgeLike, args: dict) -> dict:
    """The lab's extension: the entities of `kind` (publisher, subscription, client, action_client)
    on `name`, each with its node and QoS, as their clients told them (capabilities/endpoints.py); a
    client on the topic that told none (roslibpy, rospy) and the lab's node count as one entity each,
    QoS unknown. `action_server`: the node that serves the action (the lab's own or a node's), never told."""
    kind, name = str(args.get("kind", "")), "/" + str(args.get("name", "")).strip("/")
    if kind not in LISTED_KINDS:
        raise ServiceFailure(f"/rosapi/endpoints: 'kind' must be one of {', '.join(LISTED_KINDS)}")
    if kind == "action_server":
        server = bridge.actions.server_node(name)
        return {"endpoints": [{"node": server, "qos": {}}] if server else []}
    if kind == "publisher":
        lab, detail = LAB_NODE in _publishers(bridge, {"topic": name})["publishers"], "publishing"
    elif kind == "subscription":
        lab, detail = LAB_NODE in _subscribers(bridge, {"topic": name})["subscribers"], "subscribing"
    else:
        lab, detail = False, ""
    entities = [{"node": LAB_NODE, "qos": {}}] if lab else []
    for session in bridge.sessions.all():
        told = session.endpoints(kind, name)
        entities += told or (
            [{"node": session.name, "qos": {}}] if detail and name in session.details()[detail] else []
        )
    return {"endpoints": entities}


def _nodes(bridge: BridgeLike, args: dict) -> dict:
    return {"nodes": [LAB_NODE] + [n for s in bridge.sessions.all() for n in (s.node_names or [s.client_name])]}


def _node_details(bridge: BridgeLike, args: dict) -> dict:
    node = str(args.get("node", ""))
    if node == LAB_NODE:
        return {
            "subscribing": [bridge.topics.command_topic, *bridge.tf.inputs],
            "publishing": [t for t in bridge.topics.types() if bridge.topics.lab_publishes(t)],
            "services": [s.name for s in bridge.services.registry() if bridge.services.lab_provides(s.name)],
        }
    other = next((s for s in bridge.sessions.all() if node in (s.node_names or [s.client_name])), None)
    if other is None:
        return {"subscribing": [], "publishing": [], "services": []}
    return other.details()


def _action_servers(bridge: BridgeLike, args: dict) -> dict:
    return {"action_servers": bridge.actions.names()}


def _get_time(bridge: BridgeLike, args: dict) -> dict:
    time = bridge.lab.snapshot().time
    sec = int(time)
    nanosec = int(round((time - sec) * 1e9))
    # ROS 2 builtin_interfaces/Time (sec, nanosec); roslibpy's get_time reads ROS 1's secs/nsecs
    return {"time": {"sec": sec, "nanosec": nanosec, "secs": sec, "nsecs": nanosec}}


def _parameters(name: str, handler: Callable[[Any, dict], dict]) -> Handler:
    """A parameter service: it reads the lab's parameters; a malformed name is a failed call."""

    def parameters(bridge: BridgeLike, args: dict) -> dict:
        try:
            return handler(bridge.lab, args)
        except ParamError as error:
            raise ServiceFailure(f"{name}: {error}") from None

    return parameters


@dataclass(frozen=True)
class RosapiService:
    """One rosapi service: its name, type (rosapi's ROS 1 spelling), handler, and whether it
    changes the lab (with a token set, the caller must have presented it)."""

    name: str
    type: str
    handler: Handler
    writes: bool = False


SERVICES = (
    RosapiService("/rosapi/topics", "rosapi/Topics", _topics),
    RosapiService("/rosapi/topic_type", "rosapi/TopicType", _topic_type),
    RosapiService("/rosapi/topics_for_type", "rosapi/TopicsForType", _topics_for_type),
    RosapiService("/rosapi/topics_and_raw_types", "rosapi/TopicsAndRawTypes", _topics_and_raw_types),
    RosapiService("/rosapi/services", "rosapi/Services", _services),
    RosapiService("/rosapi/service_type", "rosapi/ServiceType", _service_type),
    RosapiService("/rosapi/services_for_type", "rosapi/ServicesForType", _services_for_type),
    RosapiService("/rosapi/service_request_details", "rosapi/ServiceRequestDetails", _details("request")),
    RosapiService("/rosapi/service_response_details", "rosapi/ServiceResponseDetails", _details("response")),
    RosapiService("/rosapi/message_details", "rosapi/MessageDetails", _message_details),
    RosapiService("/rosapi/nodes", "rosapi/Nodes", _nodes),
    RosapiService("/rosapi/node_details", "rosapi/NodeDetails", _node_details),
    RosapiService("/rosapi/publishers", "rosapi/Publishers", _publishers),
    RosapiService("/rosapi/subscribers", "rosapi/Subscribers", _subscribers),
    RosapiService("/rosapi/action_servers", "rosapi/GetActionServers", _action_servers),
    RosapiService("/rosapi/endpoints", "rosapi/Endpoints", _endpoints),
    RosapiService("/rosapi/get_time", "rosapi/GetTime", _get_time),
    RosapiService("/rosapi/get_param", "rosapi/GetParam", _parameters("get_param", _get_param)),
    RosapiService("/rosapi/has_param", "rosapi/HasParam", _parameters("has_param", _has_param)),
    RosapiService("/rosapi/search_param", "rosapi/SearchParam", _parameters("search_param", _search_param)),
    RosapiService("/rosapi/get_param_names", "rosapi/GetParamNames", _parameters("get_param_names", _get_param_names)),
    RosapiService("/rosapi/set_param", "rosapi/SetParam", _parameters("set_param", _set_param), writes=True),
    RosapiService(
        "/rosapi/delete_param", "rosapi/DeleteParam", _parameters("delete_param", _delete_param), writes=True
    ),
)
