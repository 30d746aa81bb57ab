"""Parameters as ROS 2 has them: declared with a type, default, description, range and read-only
flag, per node; get / set / list / describe / dump / load (YAML) with rclcpp's refusal messages.

One declaration per parameter (HTTP: app/api/params.py); `apply` runs in the simulation so a change takes effect
in the running controller or simulation; `read` (when given) reads the value from the world, for
values that services also change (f_n_min is set by start/stop_cooperative_lifting).
Deviation from ROS 2: JSON has one number type, so an integer is accepted for a double.
Nodes that declare their own parameters (an rclpy node over rosbridge) join through `remote`: their
parameters are listed, read, set and described through the node's standard parameter services.
"""

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, Protocol, TypeVar

import yaml

from sim.ranges import range_refusal

from app.ros.names import node_name
from interfaces.json_value import JSON

T = TypeVar("T")
ParamType = Literal["double", "integer", "string", "bool"]
MAX_FILE_BYTES = 64 * 1024  # a parameter file (a dump of all of the lab's is ~1 KB)
MAX_FILE_DEPTH = 16  # nesting of lists and mappings (a dump has 3)
MAX_FILE_NODES = 10_000  # scalars, lists and mappings
PY_TYPES = {"double": (float, int), "integer": (int,), "string": (str,), "bool": (bool,)}


@dataclass(frozen=True)
class Parameter:
    node: str
    name: str
    type: ParamType
    default: JSON
    description: str
    range: tuple[float, float] | None = None
    read_only: bool = False
    choices: tuple[str, ...] = ()  # allowed strings (checked like an on_set callback)
    apply: Callable[[Any, Any], None] | None = None  # (world, value), on the loop thread
    read: Callable[[Any], Any] | None = None  # (world) -> value, on the loop thread
    offline: Callable[[Any, Any], Any] | None = None  # (setup, value) -> setup of a headless run; None: not applicable

    def describe(self) -> dict:
        out = {
            "node": self.node,
            "name": self.name,
            "type": self.type,
            "description": self.description,
            "read_only": self.read_only,
            "default": self.default,
        }
        if self.range is not None:
            out["min_value"], out["max_value"] = self.range
        if self.choices:
            out["choices"] = list(self.choices)
        return out


def type_name(value: object) -> str:
    """The ROS 2 type name of a JSON/YAML value."""
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "double"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    return "not set" if value is None else type(value).__name__


class ParameterRefused(Exception):
    """rclcpp's reason for refusing a set (the message)."""

    def __init__(self, reason: str, status: int = 422) -> None:
        super().__init__(reason)
        self.status = status


class RemoteParameters(Protocol):
    """The parameters of nodes that run elsewhere (a rosbridge client's rclpy node), reached through
    the node's own parameter services: app/ros/node_params.py. Each method raises
    ParameterRefused with the node's reason (or why the node could not be asked)."""

    def nodes(self) -> list[str]: ...  # the nodes whose parameters can be reached now

    def names(self, node: str) -> list[str]: ...

    def get(self, node: str, names: list[str]) -> list[JSON]: ...  # None: not set

    def set(self, node: str, name: str, value: JSON) -> None: ...

    def describe(self, node: str, name: str) -> dict: ...  # Parameter.describe()'s shape


class Simulation(Protocol):
    """What the parameter server uses of the lab (app/worlds/port.py's LabPort has it): a function
    run on the simulation's world between two steps (a parameter's apply and read)."""

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T: ...


class ParameterServer:
    """The lab's declared parameters, and (through `remote`) those of nodes that declare their own:
    one registry for HTTP, the CLI, the page and rosapi."""

    def __init__(self, declarations: list[Parameter], lab: Simulation | None) -> None:
        """lab: where a parameter's apply and read run; None: a validator (validate() only)."""
        self.lab = lab
        self.declarations = {(p.node, p.name): p for p in declarations}
        self.values = {(p.node, p.name): p.default for p in declarations}
        self.remote: RemoteParameters | None = None  # set by the server that reaches nodes (rosbridge)

    def remote_node(self, node: str) -> bool:
        """`node` is a node's that declares its own parameters (not one of the lab's)."""
        node = node_name(node)
        return self.remote is not None and all(n != node for n, _ in self.declarations) and node in self.remote.nodes()

    def _simulation(self) -> Simulation:
        """The lab a parameter's apply and read run on (a validator has none: it never gets there)."""
        if self.lab is None:
            raise RuntimeError("this parameter server only validates: it has no simulation to apply to")
        return self.lab

    def number(self, node: str, name: str) -> float:
        """A number parameter's value (double or integer) as a float."""
        value = self.get(node, name)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParameterRefused(f"parameter '{name}' is not a number: {type_name(value)}")
        return float(value)

    def _remote(self) -> "RemoteParameters":
        """The nodes' parameters (set whenever remote_node() said yes)."""
        assert self.remote is not None
        return self.remote

    def has(self, node: str, name: str) -> bool:
        if (node_name(node), name) in self.declarations:
            return True
        if self.remote_node(node):
            try:
                return name in self._remote().names(node_name(node))
            except ParameterRefused:
                return False
        return False

    def typed(self, node: str, name: str) -> tuple[str, JSON]:
        """(type, value) of a parameter, declared here or by its node."""
        if self.remote_node(node) and (node_name(node), name) not in self.declarations:
            value = self.get(node, name)
            return type_name(value), value
        value = self.get(node, name)
        return self.declaration(node, name).type, value

    def describe(self, node: str, name: str) -> dict:
        param = self.declarations.get((node_name(node), name))
        if param is not None:
            return param.describe()
        if self.remote_node(node):
            return self._remote().describe(node_name(node), name)
        raise ParameterRefused("Parameter not set.", 404)

    def declaration(self, node: str, name: str) -> Parameter:
        param = self.declarations.get((node_name(node), name))
        if param is None:
            raise ParameterRefused(f"parameter '{name}' cannot be set because it was not declared", 404)
        return param

    def get(self, node: str, name: str) -> JSON:
        param = self.declarations.get((node_name(node), name))
        if param is None and self.remote_node(node):
            value = self._remote().get(node_name(node), [name])[0]
            if value is None:
                raise ParameterRefused("Parameter not set.", 404)
            return value
        if param is None:
            raise ParameterRefused("Parameter not set.", 404)
        if param.read is not None:
            return self._simulation().call(param.read)
        return self.values[(param.node, param.name)]

    def set(self, node: str, name: str, value: JSON, force: bool = False) -> None:
        """Set or raise ParameterRefused with rclcpp's reason (a node's: its own reason). force: skip
        read-only (start-up files)."""
        if (node_name(node), name) not in self.declarations and self.remote_node(node):
            self._remote().set(node_name(node), name, value)
            return
        param, value = self.validate(node, name, value, force)
        if param.apply is not None:
            self._simulation().call(param.apply, value)
        self.values[(param.node, param.name)] = value

    def validate(self, node: str, name: str, value: JSON, force: bool = False) -> tuple[Parameter, JSON]:
        """(declaration, value as stored) or ParameterRefused with rclcpp's reason; changes nothing."""
        param = self.declaration(node, name)
        if param.read_only and not force:
            raise ParameterRefused(f"parameter '{name}' cannot be set because it is read-only")
        if not isinstance(value, PY_TYPES[param.type]) or (param.type != "bool" and isinstance(value, bool)):
            raise ParameterRefused(
                f"Wrong parameter type, parameter {{{name}}} is of type {{{param.type}}}, "
                f"setting it to {{{type_name(value)}}} is not allowed."
            )
        if param.type == "double":
            value = float(value)
        if param.range is not None and isinstance(value, (int, float)):  # a range: a number's (declarations)
            low, high = param.range
            kind = "floating point" if param.type == "double" else "integer"
            if refusal := range_refusal(name, value, low, high, kind):
                raise ParameterRefused(refusal)
        if param.choices and value not in param.choices:
            raise ParameterRefused(f"Parameter {{{name}}} must be one of {', '.join(param.choices)}.")
        return param, value

    def names(self) -> list[tuple[str, str]]:
        """(node, name) of every parameter: the lab's, then each node's that answers."""
        out = list(self.declarations)
        if self.remote is not None:
            declared_nodes = {n for n, _ in self.declarations}
            for node in self.remote.nodes():
                if node not in declared_nodes:
                    try:
                        out += [(node, name) for name in self._remote().names(node)]
                    except ParameterRefused:
                        continue
        return out

    def items(self) -> list[tuple[Parameter, JSON]]:
        """Every parameter with its value: the lab's, then each node's (a node that does not
        answer is left out)."""
        out = [(p, self.get(p.node, p.name)) for p in self.declarations.values()]
        if self.remote is not None:
            declared_nodes = {n for n, _ in self.declarations}
            for node in self.remote.nodes():
                if node in declared_nodes:
                    continue
                try:
                    names = self._remote().names(node)
                    values = self._remote().get(node, names) if names else []
                except ParameterRefused:
                    continue
                out += [
                    (Parameter(node, name, type_name(value), None, ""), value)  # type: ignore[arg-type]
                    for name, value in zip(names, values)
                ]
        return out

    def dump(self, node: str | None = None) -> str:
        """YAML like `ros2 param dump`: node: {ros__parameters: {name: value}}."""
        tree: dict[str, dict] = {}
        for param, value in self.items():
            if node is None or param.node == node_name(node):
                tree.setdefault(param.node, {"ros__parameters": {}})["ros__parameters"][param.name] = value
        return yaml.safe_dump(tree, sort_keys=False)

    def load(self, text: str, force: bool = False) -> list[dict]:
        """Set every parameter of a dump; one result per parameter (like `ros2 param load`)."""
        tree = parse_parameter_file(text)
        if not isinstance(tree, dict):
            raise ParameterRefused(
                "a parameter file maps node names to {ros__parameters: {...}}, as `hri-lab param dump` writes it"
            )
        results = []
        for node, body in tree.items():
            params = body.get("ros__parameters") if isinstance(body, dict) else None
            if not isinstance(params, dict):
                raise ParameterRefused(f"node '{node}' has no ros__parameters mapping")
            for name, value in params.items():
                try:
                    self.set(str(node), str(name), value, force=force)
                    results.append({"node": node_name(str(node)), "name": name, "successful": True, "reason": ""})
                except ParameterRefused as refused:
                    results.append(
                        {"node": node_name(str(node)), "name": name, "successful": False, "reason": str(refused)}
                    )
        return results


FILE_FORMAT = "YAML mapping node names to {ros__parameters: {name: value}}, as `hri-lab param dump` writes it"


def read_parameter_file(path: str | Path) -> str:
    """The text of a parameter file, or ParameterRefused saying what the file is instead: missing,
    a folder, larger than MAX_FILE_BYTES, or not UTF-8 text (e.g. a recording handed by mistake).
    The callers name the file before the reason, as they do for the refusals of its contents."""
    path = Path(path)
    if path.is_dir():
        raise ParameterRefused(f"a folder, not a parameter file ({FILE_FORMAT})")
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise ParameterRefused("no such file") from None
    except OSError as exc:
        raise ParameterRefused(f"cannot read it: {exc.strerror}") from None
    if len(data) > MAX_FILE_BYTES:
        raise ParameterRefused(
            f"not a parameter file (larger than {MAX_FILE_BYTES} bytes; a parameter file is {FILE_FORMAT})"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise ParameterRefused(
            f"not a parameter file (binary, not UTF-8 text; a parameter file is {FILE_FORMAT})"
        ) from None


def parse_parameter_file(text: str) -> JSON:
    """The YAML of a parameter file, within MAX_FILE_BYTES, MAX_FILE_DEPTH and MAX_FILE_NODES;
    anything else (too big, too deep, aliases that expand, invalid YAML) raises ParameterRefused.
    The limits are checked on the parser's events (no recursion) before anything is built."""
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > MAX_FILE_BYTES:
        raise ParameterRefused(f"a parameter file is at most {MAX_FILE_BYTES} bytes, got {size}")
    depth = nodes = 0
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)  # libyaml when installed: fast
    try:
        for event in yaml.parse(text, Loader=loader):
            if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
                depth += 1
                if depth > MAX_FILE_DEPTH:
                    raise ParameterRefused(f"a parameter file nests at most {MAX_FILE_DEPTH} levels")
            elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                depth -= 1
            elif isinstance(event, yaml.AliasEvent):
                raise ParameterRefused("a parameter file has no YAML aliases (*name)")
            if isinstance(event, yaml.NodeEvent):
                nodes += 1
                if nodes > MAX_FILE_NODES:
                    raise ParameterRefused(f"a parameter file has at most {MAX_FILE_NODES} values")
        return yaml.load(text, Loader=loader)
    except yaml.YAMLError as exc:
        raise ParameterRefused(f"invalid YAML: {str(exc)[:300]}") from None
    except (RecursionError, ValueError, OverflowError) as exc:  # e.g. a timestamp out of range
        raise ParameterRefused(f"invalid parameter file: {type(exc).__name__}: {str(exc)[:200]}") from None
