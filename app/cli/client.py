"""`hri-lab service|param|topic ...`: ros2-like commands against a running server (--url).

httpx, websockets and yaml are imported by the commands that use them, not with this module: every
`hri-lab` command builds its parser from this one, and `hri-lab run` and `launch`, which parse their
arguments here and send nothing, start without them (httpx's import, with the rich, click and
pygments of its own command line, was most of a CLI start's CPU; websockets' and yaml's half of the
rest: docs/performance.md, "The commands' start")."""

from __future__ import annotations

import argparse
import functools
import json
import os
import sys
import time
from typing import TYPE_CHECKING

from app.cli import arguments
from app.ros.names import absolute, node_name
from rosclient.headers import lab_headers

if TYPE_CHECKING:
    import httpx


class CliError(Exception):
    pass


def _headers(args) -> dict[str, str]:
    """The lab's token ($HRI_LAB_TOKEN) and, behind a JupyterHub, the student's hub token (app/tokens.py)."""
    return lab_headers(args.url, os.environ.get("HRI_LAB_TOKEN"))


def _client(args) -> httpx.Client:
    import httpx

    headers = _headers(args)
    return httpx.Client(base_url=args.url, timeout=10.0, headers=headers)


def _request(args, method: str, path: str, **kwargs) -> httpx.Response:
    import httpx

    try:
        with _client(args) as client:
            return client.request(method, path, **kwargs)
    except httpx.HTTPError as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None


def _unreachable(*also: type[Exception]) -> tuple[type[Exception], ...]:
    """What a rosbridge connection that fails raises, and `also` (`except _unreachable():` imports
    websockets only when one did)."""
    from websockets.exceptions import WebSocketException

    return (OSError, TimeoutError, WebSocketException, *also)


def _yaml_arg(text: str) -> dict:
    import yaml

    try:
        value = yaml.safe_load(text) if text.strip() else {}
    except yaml.YAMLError as exc:
        raise CliError(f"invalid YAML: {exc}") from None
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise CliError("the request must be a YAML mapping, e.g. '{a: 1, b: 2}'")
    return value


def _message(type_name: str, suffix: str, values: dict) -> str:
    """A request or response as ros2 service call prints it: the message's repr, `pkg.srv.Name_Response(...)`."""
    fields = ", ".join(f"{k}={v!r}" for k, v in values.items())
    return f"{_ros2_type(type_name, 'srv').replace('/', '.')}_{suffix}({fields})"


def _detail(response: httpx.Response) -> str:
    try:
        body = response.json()
    except ValueError:
        return response.text
    detail = body.get("detail", body) if isinstance(body, dict) else body
    if isinstance(detail, list):  # FastAPI validation errors
        return "; ".join(
            f"{'.'.join(str(x) for x in e.get('loc', [])[1:]) or 'request'}: {e.get('msg')}" for e in detail
        )
    return str(detail)


def _ros2_type(type_name: str, kind: str) -> str:
    from app.cli import graph

    return graph.ros2_type(type_name, kind)


def _print_list(args, path: str, kind: str) -> int:
    """`ros2 X list [-t] [-c]`: one name per line, sorted by name as the graph's names come from rmw,
    with [type] when asked (ROS 2's name: pkg/srv/Name); or their number alone."""
    listed = sorted(_request(args, "GET", path).json(), key=lambda item: item["name"])
    if args.count:
        print(len(listed))
        return 0
    for item in listed:
        print(f"{item['name']} [{_ros2_type(item['type'], kind)}]" if args.show_types else item["name"])
    return 0


def _named_types(args, path: str) -> dict[str, str]:
    """The lab's listing at `path` (/services, /topics, /actions): name -> type, as the lab names it."""
    return {item["name"]: item["type"] for item in _request(args, "GET", path).json()}


def _service_find(args) -> int:
    """`ros2 service find TYPE [-c]`: the services of a type (`pkg/srv/Name`, or `pkg/Name`), by name."""
    return _of_type(_named_types(args, "/services"), args.type, "srv", args.count_services)


def _lookup(args, kind: str) -> tuple[str, httpx.Response]:
    """`/name` and the server's answer for GET /{kind}/name; a clear error when there is none."""
    name = absolute(args.name)
    response = _request(args, "GET", f"/{kind}{name}")
    if response.status_code != 200:
        raise CliError(f"{kind[:-1]} '{name}' is not available: {_detail(response)}")
    return name, response


# --- service ----------------------------------------------------------------------------------
def service(args) -> int:
    if args.action == "list":
        return _print_list(args, "/services", "srv")
    if args.action == "find":
        return _service_find(args)
    name, info = _lookup(args, "services")
    info = info.json()
    if args.action == "type":
        print(_ros2_type(info["type"], "srv"))
        return 0
    if args.action == "info":  # its clients as the programs told the lab (rclpy's; rospy's proxies are not told)
        from app.cli import graph

        clients = len(graph.endpoints(args.url, "client", name))
        print(f"Type: {_ros2_type(info['type'], 'srv')}\nClients count: {clients}\nServices count: 1")
        return 0
    if args.action == "show":
        print(info["srv"])
        return 0
    return _service_call(args, name, info["type"])


def _service_call(args, name: str, type_name: str) -> int:
    """`service call NAME [TYPE] VALUES|--stdin [-r HZ]` as ros2service's call verb prints it (each
    request and response followed by a blank line); `-r`: the call again at that rate until Ctrl+C.
    Unlike ros2, a failed call ends the command with status 1, its reason on stderr."""
    request = _typed_yaml(args, type_name, "srv", "request")
    period = None if args.rate is None else 1.0 / args.rate
    try:
        while True:
            print(f"requester: making request: {_message(type_name, 'Request', request)}\n", flush=True)
            last_call = time.monotonic()
            response = _request(args, "POST", f"/services{name}", json=request)
            if response.status_code != 200:
                print(f"service call failed: {_detail(response)}", file=sys.stderr)
                return 1
            print(f"response:\n{_message(type_name, 'Response', response.json())}\n", flush=True)
            if period is None:
                return 0
            time.sleep(max(0.0, last_call + period - time.monotonic()))
    except KeyboardInterrupt:
        return 0


def _typed_values(args, type_name: str, kind: str) -> str:
    """The YAML values of `call NAME [TYPE] [VALUES]` (ros2's form names the type): a type given must
    be the interface's own, `pkg/kind/Name` or `pkg/Name`."""
    first, second = args.type_or_values or "", args.values or ""
    if not second and not _looks_like_type(first):
        return first  # `call NAME VALUES` (rosservice's form, and this lab's)
    given = first.replace(f"/{kind}/", "/")
    if given != type_name.replace(f"/{kind}/", "/"):
        package, _, name = type_name.replace(f"/{kind}/", "/").partition("/")
        raise CliError(f"the type {first!r} is not the {kind}'s: {package}/{kind}/{name}")
    return second


def _typed_yaml(args, type_name: str, kind: str, what: str) -> dict:
    """The `what` (request, goal) of `call NAME [TYPE] [VALUES]`: the values given (`_typed_values`),
    or with --stdin the YAML standard input holds (ros2's collect_stdin), never both."""
    text = _typed_values(args, type_name, kind)
    if args.stdin:
        if text:
            raise CliError(f"--stdin reads the {what} from standard input: give no values after the type")
        text = sys.stdin.read()
    return _yaml_arg(text)


def _looks_like_type(text: str) -> bool:
    return bool(text) and "/" in text and not any(c in text for c in "{}[]:' \"")


# --- param ------------------------------------------------------------------------------------
VALUE_WORDS = {"double": "Double", "integer": "Integer", "string": "String", "bool": "Boolean"}


def param(args) -> int:
    node = node_name(getattr(args, "node", None) or "")
    if args.action == "get" and args.name is None:  # one name: ROS 1's parameter server (rosparam get)
        return _ros1_param(args, args.node)
    actions = {
        "list": _param_list,
        "get": _param_get,
        "set": _param_set,
        "delete": _param_delete,
        "describe": _param_describe,
        "dump": _param_dump,
        "load": _param_load,
    }
    if args.action not in actions:
        raise CliError(f"unknown param action {args.action}")
    return actions[args.action](args, node)


def _param_list(args, node: str) -> int:
    current = None
    for p in _request(args, "GET", "/params").json():
        if node and p["node"] != node:
            continue
        if p["node"] != current:
            current = p["node"]
            print(f"/{current}:")
        print(f"  {p['name']}")
    return 0


def _param_get(args, node: str) -> int:
    response = _request(args, "GET", f"/params/{node}/{args.name}")
    if response.status_code != 200:
        print(response.json().get("reason", "Parameter not set."))
        return 1
    body = response.json()
    print(f"{VALUE_WORDS.get(body['type'], 'Value')} value is: {body['value']}")
    return 0


def _param_set(args, node: str) -> int:
    import yaml

    value = yaml.safe_load(args.value)
    response = _request(args, "PUT", f"/params/{node}/{args.name}", json={"value": value})
    body = response.json()
    if body.get("successful"):
        print("Set parameter successful")
        return 0
    print(f"Setting parameter failed: {body.get('reason')}")
    return 1


def _param_describe(args, node: str) -> int:
    response = _request(args, "GET", f"/params/{node}/{args.name}/describe")
    if response.status_code != 200:
        print("Parameter not set")
        return 1
    d = response.json()
    print(f"Parameter name: {d['name']}\n  Type: {d['type']}\n  Description: {d['description']}")
    constraints = []
    if d.get("read_only"):
        constraints.append("    Read only: true")
    if "min_value" in d:
        constraints += [f"    Min value: {d['min_value']}", f"    Max value: {d['max_value']}"]
    if d.get("choices"):
        constraints.append(f"    One of: {', '.join(d['choices'])}")
    if constraints:
        print("  Constraints:\n" + "\n".join(constraints))
    return 0


def _param_dump(args, node: str) -> int:
    print(_request(args, "GET", "/params/dump", params={"node": node} if node else None).text, end="")
    return 0


def _param_load(args, node: str) -> int:
    from app.ros.params import ParameterRefused, read_parameter_file

    try:
        text = read_parameter_file(args.file)
    except ParameterRefused as exc:
        raise CliError(f"{args.file}: {exc}") from None
    response = _request(
        args, "POST", "/params/load", content=text.encode("utf-8"), headers={"content-type": "application/yaml"}
    )
    body = response.json()
    if "results" not in body:
        print(f"Loading parameters failed: {body.get('reason')}")
        return 1
    for r in body["results"]:
        print(
            f"Set parameter {r['name']} successful"
            if r["successful"]
            else f"Set parameter {r['name']} failed: {r['reason']}"
        )
    return 0 if body["successful"] else 1


def _param_delete(args, node: str) -> int:
    """`ros2 param delete NODE NAME`: the node's set_parameters with the value PARAMETER_NOT_SET (the
    lab's nodes and the programs', as `param set` reaches them), its answer as ros2 prints it."""
    response = _request(args, "PUT", f"/params/{node}/{args.name}", json={"value": None})
    if response.status_code == 404 and not _node_known(args, node):
        print("Node not found", file=sys.stderr)
        return 1
    body = response.json()
    reason = str(body.get("reason") or "")
    if body.get("successful"):
        print("Deleted parameter successfully" + (f": {reason}" if reason else ""))
        return 0
    print("Deleting parameter failed" + (f": {reason}" if reason else ""), file=sys.stderr)
    return 1


def _node_known(args, node: str) -> bool:
    """A node of the lab's parameters or of the graph."""
    from app.cli import graph

    if any(p["node"] == node for p in _request(args, "GET", "/params").json()):
        return True
    try:
        return "/" + node.strip("/") in graph.node_list(args.url)
    except _unreachable():
        return False


def _ros1_param(args, name: str) -> int:
    """`rosparam get NAME`: the value of a ROS 1 parameter (e.g. /robot_description), asked of the
    lab's rosapi over its rosbridge endpoint, as rospy's get_param does; a string printed as is."""
    ws_url = args.url.replace("http://", "ws://").replace("https://", "wss://").rstrip("/") + "/"
    request = {"op": "call_service", "id": "param_get", "service": "/rosapi/get_param", "args": {"name": name}}
    from websockets.sync.client import connect

    from app.cli.graph import MAX_MESSAGE_BYTES

    try:
        with connect(ws_url, open_timeout=10, max_size=MAX_MESSAGE_BYTES, additional_headers=_headers(args)) as ws:
            ws.send(json.dumps(request))
            while True:
                answer = json.loads(ws.recv(timeout=10))
                if answer.get("op") == "service_response" and answer.get("id") == "param_get":
                    break
    except _unreachable(ValueError) as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None
    if not answer.get("result"):
        raise CliError(f"cannot get {name}: {answer.get('values')}")
    value = json.loads(answer["values"]["value"])
    if value is None:
        print(f"ERROR: Parameter [{absolute(name)}] is not set", file=sys.stderr)
        return 1
    print(
        value if isinstance(value, str) else _dump(value),
        end="" if isinstance(value, str) and value.endswith("\n") else "\n",
    )
    return 0


# --- topic ------------------------------------------------------------------------------------
def _graph_topics(args) -> dict[str, str]:
    """The graph's topics over rosbridge (the programs' own included); none when it cannot be asked."""
    from app.cli import graph

    try:
        return graph.topics(args.url)
    except _unreachable(ValueError):
        return {}


def _all_topics(args) -> dict[str, str]:
    """Every topic, the lab's and the programs': name -> its type (as the lab names it)."""
    listed = _named_types(args, "/topics")
    for name, type_name in _graph_topics(args).items():
        listed.setdefault(name, type_name)
    return listed


def _type_of(found: dict[str, str], name: str, kind: str) -> int:
    """`ros2 topic type NAME`, `ros2 action type NAME`: its type as ROS 2 names it; for a name the
    graph does not have (compared as given, as ros2 compares it), nothing printed and status 1."""
    if name not in found:
        return 1
    print(_ros2_type(found[name], kind))
    return 0


def _of_type(found: dict[str, str], wanted: str, kind: str, count: bool) -> int:
    """`ros2 topic find TYPE`, `ros2 action find TYPE` [-c]: the names of that type, sorted (the type
    as ROS 2 names it, `pkg/msg/Name`, or `pkg/Name`); with -c their number alone."""
    names = sorted(n for n, t in found.items() if _ros2_type(t, kind) == _ros2_type(wanted.strip("/"), kind))
    if count:
        print(len(names))
    for name in [] if count else names:
        print(name)
    return 0


def _topic_list(args) -> int:
    """`ros2 topic list [-t] [-c]`: the lab's topics and the programs', sorted as ros2 sorts them (types
    as ROS 2 names them); or their number alone."""
    listed = _all_topics(args)
    if args.count:
        print(len(listed))
        return 0
    for name in sorted(listed):
        print(f"{name} [{_ros2_type(listed[name], 'msg')}]" if args.show_types else name)
    return 0


def _program_topic_echo(args, name: str, failure: httpx.Response) -> int:
    """`topic echo` of a topic a program publishes (not one of the lab's): its messages over rosbridge."""
    from app.cli import graph

    type_name = _graph_topics(args).get(name)
    if not type_name:
        raise CliError(f"topic '{name}' is not available: {_detail(failure)}")
    wanted = 1 if args.once else args.count
    received = 0
    try:
        for message in graph.messages(args.url, name, type_name):
            _print_message(message)
            received += 1
            if wanted is not None and received >= wanted:
                break
    except KeyboardInterrupt:
        pass
    return 0


def _graph_type(args, name: str) -> str:
    """The type of a topic of the graph (the lab's or a program's), or 'Unknown topic' as ros2 says it."""
    type_name = _graph_topics(args).get(name)
    if type_name is None:
        type_name = next((i["type"] for i in _request(args, "GET", "/topics").json() if i["name"] == name), None)
    if type_name is None:
        raise CliError(f"Unknown topic '{name}'")
    return type_name


def _topic_info(args, name: str) -> int:
    """`ros2 topic info NAME [-v]`: its type (ROS 2's name) and its publishers and subscriptions,
    counted as the entities the programs told the lab (a client that told none as one); with -v each
    one's node, type and QoS as rclpy's TopicEndpointInfo prints it (app/cli/graph.py `endpoints`)."""
    from app.cli import graph

    type_name = _ros2_type(_graph_type(args, name), "msg")
    end = "\n\n" if args.verbose else "\n"
    print(f"Type: {type_name}", end=end)
    for kind, title in (("publisher", "Publisher"), ("subscription", "Subscription")):
        found = graph.endpoints(args.url, kind, name)
        print(f"{title} count: {len(found)}", end=end)
        for entity in found if args.verbose else []:
            print(_endpoint_info(entity, type_name, kind), end=end)
    return 0


def _endpoint_info(entity: dict, type_name: str, kind: str) -> str:
    """One endpoint as rclpy's TopicEndpointInfo prints it, less the type hash and the GID the lab
    has not got; a QoS the program did not tell is rmw's default for the policy (durations: Infinite)."""
    namespace, _, node = str(entity.get("node", "")).rpartition("/")
    qos = entity.get("qos") or {}

    def duration(key: str) -> str:
        nanoseconds = qos.get(key, 0)
        return f"{int(nanoseconds)} nanoseconds" if nanoseconds else "Infinite"

    return "\n".join(
        [
            f"Node name: {node}",
            f"Node namespace: {namespace or '/'}",
            f"Topic type: {type_name}",
            f"Endpoint type: {kind.upper()}",
            "QoS profile:",
            f"  Reliability: {qos.get('reliability', 'RELIABLE')}",
            "  History (Depth): UNKNOWN",  # not told over DDS's discovery either
            f"  Durability: {qos.get('durability', 'VOLATILE')}",
            f"  Lifespan: {duration('lifespan')}",
            f"  Deadline: {duration('deadline')}",
            f"  Liveliness: {qos.get('liveliness', 'AUTOMATIC')}",
            f"  Liveliness lease duration: {duration('liveliness_lease_duration')}",
        ]
    )


def _topic_pub(args, name: str) -> int:
    """`ros2 topic pub NAME TYPE [VALUES] [-1 | -t N] [-r HZ] [-w N]`: the message made of the YAML
    values (a field it does not have refused), published as ros2 publishes and prints it."""
    from app.cli import graph
    from interfaces.packages import Interfaces

    try:
        message_class = Interfaces([]).message(args.type)
    except ImportError:
        raise CliError("The passed message type is invalid") from None
    values = _yaml_arg(sys.stdin.read() if args.stdin else args.values)  # --stdin: ros2's collect_stdin
    unknown = sorted(set(values) - {f.name for f in message_class._fields})
    if unknown:
        raise CliError(f"Failed to populate field: {message_class._type} has no field '{unknown[0]}'")
    try:
        message = message_class.from_json(values)
        wire = message.to_json()
    except (TypeError, ValueError) as exc:
        raise CliError(f"Failed to populate field: {exc}") from None
    times = 1 if args.once else args.times
    wait_for = args.wait_matching_subscriptions if args.wait_matching_subscriptions is not None else int(times != 0)

    def published():
        count = 0
        while times == 0 or count < times:
            count += 1
            if count == 1:
                print("publisher: beginning loop")
            if args.print and count % args.print == 0:
                print(f"publishing #{count}: {message!r}\n", flush=True)
            yield wire

    def waiting() -> None:
        print(f"Waiting for at least {wait_for} matching subscription(s)...", flush=True)

    try:
        graph.publish(args.url, name, message_class._type, published(), 1.0 / args.rate, wait_for, waiting)
    except graph.Refused as refused:
        raise CliError(str(refused)) from None
    except KeyboardInterrupt:
        pass
    except _unreachable() as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None
    return 0


def _topic_watch(args, name: str) -> int:
    """`ros2 topic hz NAME [-w N]` and `ros2 topic bw NAME [-w N]`: printed once a second while messages come."""
    from app.cli import graph, topic_stats

    type_name = _graph_type(args, name)
    rate = topic_stats.Rate(args.window or topic_stats.HZ_WINDOW)
    bandwidth = topic_stats.Bandwidth(args.window or topic_stats.BW_WINDOW)
    if args.action == "bw":
        print(f"Subscribed to [{name}]", flush=True)
    printed = time.monotonic()
    try:
        for _, size in graph.frames(args.url, name, type_name):
            now = time.monotonic()
            rate.arrived(now)
            bandwidth.arrived(now, size)
            if now - printed >= REPORT_PERIOD_S:
                printed = now
                lines = rate.report() if args.action == "hz" else bandwidth.report(now)
                if lines:
                    print(lines, flush=True)
    except KeyboardInterrupt:
        pass
    except _unreachable() as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None
    return 0


REPORT_PERIOD_S = 1.0  # s between the lines of topic hz and bw (ros2's timer)
TOPIC_VERBS = {"info": _topic_info, "pub": _topic_pub, "hz": _topic_watch, "bw": _topic_watch}


def topic(args) -> int:
    if args.action == "list":
        return _topic_list(args)
    if args.action == "type":
        return _type_of(_all_topics(args), args.name, "msg")
    if args.action == "find":
        return _of_type(_all_topics(args), args.type, "msg", args.count_topics)
    name = absolute(args.name)
    if args.action in TOPIC_VERBS:
        return TOPIC_VERBS[args.action](args, name)
    response = _request(args, "GET", f"/topics{name}")
    if response.status_code == 404:
        return _program_topic_echo(args, name, response)
    if response.status_code != 200:
        raise CliError(f"topic '{name}' is not available: {_detail(response)}")
    if args.once:
        _print_message(response.json())
        return 0

    ws_url = (
        args.url.replace("http://", "ws://").replace("https://", "wss://").rstrip("/")
        + f"/topics{name}/stream?rate={args.rate}"
    )
    received = 0
    from websockets.sync.client import connect

    from app.cli.graph import MAX_MESSAGE_BYTES

    try:
        with connect(ws_url, max_size=MAX_MESSAGE_BYTES, additional_headers=_headers(args)) as ws:
            while args.count is None or received < args.count:
                _print_message(json.loads(ws.recv()))
                received += 1
    except KeyboardInterrupt:
        pass
    return 0


@functools.cache
def _dumper() -> type:
    """yaml's SafeDumper with a text of several lines (a results table) as a literal block, readable as printed."""
    import yaml

    class Dumper(yaml.SafeDumper):
        pass

    Dumper.add_representer(
        str,
        lambda dumper, text: dumper.represent_scalar(
            "tag:yaml.org,2002:str", text, style="|" if "\n" in text else None
        ),
    )
    return Dumper


def _dump(value, **options) -> str:
    import yaml

    return yaml.dump(value, Dumper=_dumper(), sort_keys=False, allow_unicode=True, **options)


def _print_message(message: dict) -> None:
    print(_dump(message), end="")
    print("---", flush=True)


# --- action -----------------------------------------------------------------------------------
# A goal's end as ros2action's send_goal names it (action_msgs/GoalStatus); actionlib's PREEMPTED is CANCELED
STATUS_NAMES = {"succeeded": "SUCCEEDED", "aborted": "ABORTED", "preempted": "CANCELED"}


def _message_yaml(values: dict | None) -> str:
    """A message's values as rosidl_runtime_py's message_to_yaml writes them: block style, no line
    wrapped, ending in a newline (`{}` for a message without fields)."""
    return _dump(values or {}, width=2**31 - 1)


def _goal_as_filled(values: dict, schema: dict) -> dict:
    """The goal as ros2action sends it: every field of the Goal in its order, at its default where
    the values do not give it (rosidl's set_message_fields on a new Goal)."""
    fields = schema.get("properties", {})
    filled = {k: values[k] if k in values else f["default"] for k, f in fields.items() if k in values or "default" in f}
    return filled | {k: v for k, v in values.items() if k not in fields}


def action(args) -> int:
    if args.action == "list":
        return _print_list(args, "/actions", "action")
    if args.action == "info":
        return _action_info(args)
    if args.action in ("type", "find"):
        found = _named_types(args, "/actions")
        if args.action == "type":
            return _type_of(found, args.name, "action")
        return _of_type(found, args.type, "action", args.count_actions)
    return _send_goal(args)


def _send_goal(args) -> int:
    """`action send_goal NAME [TYPE] VALUES|--stdin [-f]`, printed as ros2action's send_goal verb
    prints it (the YAML after each heading indented on its first line only, as its format string
    does). Unlike ros2, the exit status is 1 unless the goal succeeded, and a rejection's or an
    abort's reason goes to stderr."""
    print("Waiting for an action server to become available...")
    name, info = _lookup(args, "actions")
    described = info.json()
    goal = _typed_yaml(args, described["type"], "action", "goal")
    print(f"Sending goal:\n     {_message_yaml(_goal_as_filled(goal, described.get('goal_schema', {})))}")
    response = _request(args, "POST", f"/actions{name}/goals", json=goal)
    body = response.json()
    if response.status_code == 422:
        raise CliError(f"goal refused: {_detail(response)}")
    if body.get("status") == "rejected":
        print("Goal was rejected.")
        print(f"hri-lab: the goal was rejected: {body.get('message')}", file=sys.stderr)
        return 1
    goal_id = body["goal_id"]
    print(f"Goal accepted with ID: {goal_id}\n")
    seen = 0
    while True:
        view = _request(args, "GET", f"/actions{name}/goals/{goal_id}", params={"after": seen, "wait": 5}).json()
        if args.feedback:
            for fb in view["feedback"]:
                print(f"Feedback:\n    {_message_yaml(fb)}")
        seen = view["feedback_count"]
        if view["status"] in ("succeeded", "aborted", "preempted", "rejected"):
            break
    print(f"Result:\n    {_message_yaml(view['result'])}")
    print(f"Goal finished with status: {STATUS_NAMES.get(view['status'], 'UNKNOWN')}")
    if view["status"] != "succeeded" and view.get("message"):
        print(f"hri-lab: {view['status']}: {view['message']}", file=sys.stderr)
    return 0 if view["status"] == "succeeded" else 1


def _action_info(args) -> int:
    """`action info NAME [-t] [-c]` as ros2action's info verb prints it: the action's clients (as the
    rclpy programs tell the lab: rospy's and roslibpy's are not told) and its server (the lab's node
    for the lab's own actions, the providing node for a node's), each node with the action's type
    under -t; the name as given. An action nobody serves or uses has none of either, as in ros2."""
    from app.cli import graph

    name = absolute(args.name)
    response = _request(args, "GET", f"/actions{name}")
    type_name = _ros2_type(response.json()["type"], "action") if response.status_code == 200 else ""
    try:
        told = {kind: graph.endpoints(args.url, kind, name) for kind in ("action_client", "action_server")}
    except _unreachable() as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None
    print(f"Action: {args.name}")
    for title, kind in (("Action clients", "action_client"), ("Action servers", "action_server")):
        print(f"{title}: {len(told[kind])}")
        for entity in [] if args.count else told[kind]:
            print(f"    {entity['node']}" + (f" [{type_name}]" if args.show_types and type_name else ""))
    return 0


def node(args) -> int:
    """`ros2 node list|info NAME`: the graph's nodes, the programs' and the lab's."""
    from app.cli import graph

    try:
        if args.action == "list":
            print("\n".join(graph.node_list(args.url)))
        else:
            services, actions = _named_types(args, "/services"), _named_types(args, "/actions")
            print(graph.node_info(args.url, args.name, services, actions))
    except LookupError as exc:
        raise CliError(str(exc)) from None
    except _unreachable() as exc:
        raise CliError(f"cannot reach the hri-lab server at {args.url}: {exc}") from None
    return 0


ONLY = (("msg", "only_msgs"), ("srv", "only_srvs"), ("action", "only_actions"))  # interface's -m, -s, -a


def _interface_kinds(args) -> tuple[str, ...]:
    """The kinds `-m`, `-s`, `-a` (--only-msgs, --only-srvs, --only-actions) ask for; none of them: all."""
    asked = tuple(kind for kind, flag in ONLY if getattr(args, flag, False))
    return asked or tuple(kind for kind, _ in ONLY)


def interface(args) -> int:
    """`ros2 interface list|packages|package|show`: the shipped packages' interfaces."""
    from app.cli import graph

    if args.action == "list":
        print(graph.interface_list(_interface_kinds(args)))
        return 0
    if args.action == "packages":
        print("\n".join(graph.interface_packages(_interface_kinds(args))))
        return 0
    if args.action == "package":
        try:
            text = graph.interface_package(args.package, _interface_kinds(args))
        except LookupError as exc:
            raise CliError(str(exc)) from None
        if text:
            print(text)
        return 0
    name = sys.stdin.readline().strip() if args.type == "-" else args.type  # `ros2 topic type X | ... show -`
    if not name:
        raise CliError("the passed value is empty")
    comments = "all" if args.all_comments else "none" if args.no_comments else "top"
    try:
        print(graph.interface_text(name, comments))
    except LookupError as exc:
        raise CliError(str(exc)) from None
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    url = arguments.url_parent()

    def list_parser(verbs: argparse._SubParsersAction, kind: str) -> None:
        """`list [-t] [-c]`, as ros2's list verbs take them (`-c`: --count-services and the like)."""
        listing = verbs.add_parser("list", parents=[url])
        listing.add_argument("-t", "--show-types", action="store_true", help="each one's type too")
        listing.add_argument("-c", f"--count-{kind}", dest="count", action="store_true", help="only their number")

    srv = sub.add_parser("service", help="list, inspect and call services (like ros2 service)")
    srv_sub = srv.add_subparsers(dest="action", required=True)
    list_parser(srv_sub, "services")
    for verb in ("type", "show", "info"):
        srv_sub.add_parser(verb, parents=[url]).add_argument("name")
    find = srv_sub.add_parser(
        "find", parents=[url], help="the services of a type, e.g. example_interfaces/srv/AddTwoInts"
    )
    find.add_argument("type")
    find.add_argument("-c", "--count-services", action="store_true", help="only their number")
    call = srv_sub.add_parser("call", parents=[url])
    call.add_argument("name")
    call.add_argument(
        "type_or_values", nargs="?", default="", metavar="[TYPE]", help="the service's type (ros2's form)"
    )
    call.add_argument("values", nargs="?", default="", help="request as YAML, e.g. '{a: 1, b: 2}'")
    call.add_argument("--stdin", action="store_true", help="read the request's YAML from standard input")
    call.add_argument("-r", "--rate", type=_positive_float, metavar="N", help="repeat the call at N Hz")
    srv.set_defaults(func=service)

    prm = sub.add_parser("param", help="parameters (like ros2 param)")
    prm_sub = prm.add_subparsers(dest="action", required=True)
    prm_sub.add_parser("list", parents=[url]).add_argument("node", nargs="?")
    p = prm_sub.add_parser(
        "get", parents=[url], help="a node's parameter (ros2 param get NODE NAME), or a ROS 1 one (rosparam get NAME)"
    )
    p.add_argument("node", help="the node, e.g. /cooperative_lifting; alone: a ROS 1 name, e.g. /robot_description")
    p.add_argument("name", nargs="?", help="the parameter, e.g. mu")
    p = prm_sub.add_parser("describe", parents=[url])
    p.add_argument("node")
    p.add_argument("name")
    p = prm_sub.add_parser("delete", parents=[url], help="undeclare a node's parameter (ros2 param delete NODE NAME)")
    p.add_argument("node")
    p.add_argument("name")
    p = prm_sub.add_parser("set", parents=[url])
    p.add_argument("node")
    p.add_argument("name")
    p.add_argument("value", help="YAML value, e.g. 0.5, true, sp")
    prm_sub.add_parser("dump", parents=[url]).add_argument("node", nargs="?")
    prm_sub.add_parser("load", parents=[url]).add_argument("file")
    prm.set_defaults(func=param)

    top = sub.add_parser("topic", help="topics (like ros2 topic)")
    top_sub = top.add_subparsers(dest="action", required=True)
    list_parser(top_sub, "topics")
    echo = top_sub.add_parser("echo", parents=[url], help="print the messages of a topic")
    echo.add_argument("name")
    echo.add_argument("--once", action="store_true", help="print one message and exit")
    echo.add_argument("--rate", type=float, default=10.0, help="messages per second (default 10)")
    echo.add_argument("--count", "-n", type=int, help="exit after this many messages (rostopic echo -n N)")
    top_sub.add_parser("type", parents=[url], help="its type (ros2 topic type)").add_argument("name")
    top_find = top_sub.add_parser("find", parents=[url], help="the topics of a type, e.g. std_msgs/msg/String")
    top_find.add_argument("type")
    top_find.add_argument("-c", "--count-topics", action="store_true", help="only their number")
    info = top_sub.add_parser("info", parents=[url], help="its type, publisher and subscription counts")
    info.add_argument("name")
    info.add_argument("-v", "--verbose", action="store_true", help="each publisher's and subscription's node and QoS")
    pub = top_sub.add_parser("pub", parents=[url], help="publish a message (ros2 topic pub NAME TYPE VALUES)")
    pub.add_argument("name")
    pub.add_argument("type", help="e.g. std_msgs/msg/String")
    given = pub.add_mutually_exclusive_group()
    given.add_argument("values", nargs="?", default="{}", help="the message as YAML, e.g. '{data: hello}'")
    given.add_argument("--stdin", action="store_true", help="read the message's YAML from standard input")
    pub.add_argument("-r", "--rate", type=_positive_float, default=1.0, help="publishing rate in Hz (default: 1)")
    pub.add_argument("-p", "--print", type=int, default=1, help="only print every N-th message (default: 1)")
    once = pub.add_mutually_exclusive_group()
    once.add_argument("-1", "--once", action="store_true", help="publish one message and exit")
    once.add_argument("-t", "--times", type=arguments.positive_int, default=0, help="publish N times and exit")
    pub.add_argument(
        "-w",
        "--wait-matching-subscriptions",
        type=int,
        default=None,
        help="wait for N subscriptions first (default: 1 with --once/--times, else 0)",
    )
    for verb, what in (("hz", "its average publishing rate"), ("bw", "the bandwidth it uses")):
        watch = top_sub.add_parser(verb, parents=[url], help=f"{what}, printed each second")
        watch.add_argument("name")
        watch.add_argument("-w", "--window", type=arguments.positive_int, help="the window, in messages")
    top.set_defaults(func=topic)

    act = sub.add_parser("action", help="actions (like ros2 action)")
    act_sub = act.add_subparsers(dest="action", required=True)
    list_parser(act_sub, "actions")
    act_sub.add_parser("type", parents=[url], help="its type (ros2 action type)").add_argument("name")
    act_find = act_sub.add_parser("find", parents=[url], help="the actions of a type, e.g. hri_lab/action/Count")
    act_find.add_argument("type")
    act_find.add_argument("-c", "--count-actions", "--count", action="store_true", help="only their number")
    act_info = act_sub.add_parser("info", parents=[url], help="its clients and servers (ros2 action info)")
    act_info.add_argument("name")
    act_info.add_argument("-t", "--show-types", action="store_true", help="each node with the action's type")
    act_info.add_argument("-c", "--count", action="store_true", help="only the numbers of clients and servers")
    goal = act_sub.add_parser("send_goal", parents=[url])
    goal.add_argument("name")
    goal.add_argument("type_or_values", nargs="?", default="", metavar="[TYPE]", help="the action's type (ros2's form)")
    goal.add_argument("values", nargs="?", default="", help="goal as YAML, e.g. '{count: 3}'")
    goal.add_argument("-f", "--feedback", action="store_true", help="print the feedback")
    goal.add_argument("--stdin", action="store_true", help="read the goal's YAML from standard input")
    act.set_defaults(func=action)

    nod = sub.add_parser("node", help="the graph's nodes (like ros2 node)")
    nod_sub = nod.add_subparsers(dest="action", required=True)
    nod_sub.add_parser("list", parents=[url])
    nod_sub.add_parser("info", parents=[url]).add_argument("name")
    nod.set_defaults(func=node)

    itf = sub.add_parser("interface", help="interface definitions (like ros2 interface)")
    itf_sub = itf.add_subparsers(dest="action", required=True)
    listing = itf_sub.add_parser("list", help="every interface, by kind")
    one = itf_sub.add_parser("package", help="the interfaces of a package")
    one.add_argument("package", help="e.g. example_interfaces")
    for verb in (listing, one):
        verb.add_argument("-m", "--only-msgs", action="store_true", help="only the message types")
        verb.add_argument("-s", "--only-srvs", action="store_true", help="only the service types")
        verb.add_argument("-a", "--only-actions", action="store_true", help="only the action types")
    packages = itf_sub.add_parser("packages", help="the packages with interfaces")
    packages.add_argument("-m", "--only-msgs", action="store_true", help="only the packages with messages")
    packages.add_argument("-s", "--only-srvs", action="store_true", help="only the packages with services")
    show = itf_sub.add_parser("show", parents=[url])
    show.add_argument("type", help="e.g. std_msgs/msg/String, example_interfaces/srv/AddTwoInts; - reads it from stdin")
    shown = show.add_mutually_exclusive_group()
    shown.add_argument("--all-comments", action="store_true", help="the nested definitions' comments too")
    shown.add_argument("--no-comments", action="store_true", help="no comment or blank line")
    itf.set_defaults(func=interface)


def _positive_float(text: str) -> float:
    value = float(text)
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text}")
    return value


def run(func, args) -> int:
    try:
        return func(args)
    except CliError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1


__all__ = ["add_parsers", "run"]
