"""launch_ros.actions: a node (a package's executable as `ros2 run` starts it, with its name,
namespace, parameters and remaps as --ros-args), the namespace, global parameters and remaps that
the actions after them in their group get."""

from __future__ import annotations

from typing import Any

import yaml

from launch._core import (
    Action,
    LaunchContext,
    LaunchError,
    ProcessPlan,
    Substitution,
    is_substitution,
    normalize,
    perform,
    refuse,
)
from launch.actions import ExecuteProcess
from launch_ros.parameter_descriptions import Parameter, ParameterFile, ParameterValue

__all__ = ["Node", "PushROSNamespace", "PushRosNamespace", "SetParameter", "SetParametersFromFile", "SetRemap"]

NAMESPACE = "ros_namespace"  # the launch configurations launch_ros keeps its state in, as launch_ros names them
PARAMS = "global_params"
REMAPS = "ros_remaps"


def join_namespace(base: str, namespace: str) -> str:
    if namespace.startswith("/"):
        return "/" + namespace.strip("/")
    parts = [p for p in (base.strip("/"), namespace.strip("/")) if p]
    return "/" + "/".join(parts) if parts else ""


class PushRosNamespace(Action):
    def __init__(self, namespace: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.namespace = normalize(namespace)

    def execute(self, context: LaunchContext) -> None:
        current = context.launch_configurations.get(NAMESPACE, "")
        context.launch_configurations[NAMESPACE] = join_namespace(current, perform(context, self.namespace))


PushROSNamespace = PushRosNamespace


class SetParameter(Action):
    def __init__(self, name: Any, value: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), value

    def execute(self, context: LaunchContext) -> None:
        params = list(context.launch_configurations.get(PARAMS, []))
        params.append((perform(context, self.name), _value(context, self.value)))
        context.launch_configurations[PARAMS] = params


class SetParametersFromFile(Action):
    def __init__(self, filename: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.filename = normalize(filename)

    def execute(self, context: LaunchContext) -> None:
        params = list(context.launch_configurations.get(PARAMS, []))
        params.append(perform(context, self.filename))
        context.launch_configurations[PARAMS] = params


class SetRemap(Action):
    def __init__(self, src: Any, dst: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.src, self.dst = normalize(src), normalize(dst)

    def execute(self, context: LaunchContext) -> None:
        remaps = list(context.launch_configurations.get(REMAPS, []))
        remaps.append((perform(context, self.src), perform(context, self.dst)))
        context.launch_configurations[REMAPS] = remaps


def _value(context: LaunchContext, value: Any) -> Any:
    """A parameter's value: substitutions performed and read as YAML (launch_ros's rule), a
    ParameterValue's kept as its type says, lists and dicts element by element."""
    if isinstance(value, ParameterValue):
        if value.value_type is str:
            return perform(context, value.value) if is_substitution(value.value) else str(value.value)
        return _value(context, value.value)
    if isinstance(value, dict):
        return {perform(context, k): _value(context, v) for k, v in value.items()}
    if isinstance(value, Substitution) or (
        isinstance(value, list | tuple) and value and any(isinstance(v, Substitution) for v in value)
    ):
        text = perform(context, value)
        try:
            return yaml.safe_load(text) if text.strip() else text
        except yaml.YAMLError:
            return text
    if isinstance(value, list | tuple):
        return [_value(context, v) for v in value]
    return value


class Node(ExecuteProcess):
    def __init__(
        self,
        *,
        executable: Any,
        package: Any = None,
        name: Any = None,
        namespace: Any = None,
        exec_name: Any = None,
        parameters: Any = None,
        remappings: Any = None,
        ros_arguments: Any = None,
        arguments: Any = None,
        node_executable: Any = None,
        node_name: Any = None,
        node_namespace: Any = None,
        **kwargs,
    ) -> None:
        super().__init__(cmd=[executable], name=exec_name, **kwargs)
        self.package, self.executable = package, executable or node_executable
        self.node_name, self.node_namespace = name or node_name, namespace or node_namespace
        self.parameters = list(parameters or [])
        self.remappings = list(remappings or [])
        self.ros_arguments = list(ros_arguments or [])
        self.arguments = list(arguments or [])

    def execute(self, context: LaunchContext) -> None:
        executable = perform(context, self.executable)
        if self.package is None:
            raise LaunchError(f"Node(executable='{executable}') without package=: hri-lab launch runs packages' nodes")
        found = context.runner.executable(perform(context, self.package), executable)
        ros_args: list[str] = []
        if self.node_name is not None:
            ros_args += ["-r", f"__node:={perform(context, self.node_name)}"]
        namespace = join_namespace(
            context.launch_configurations.get(NAMESPACE, ""),
            perform(context, self.node_namespace) if self.node_namespace is not None else "",
        )
        if namespace:
            ros_args += ["-r", f"__ns:={namespace}"]
        for item in [*context.launch_configurations.get(PARAMS, []), *self.parameters]:
            ros_args += self._parameters(context, item)
        for src, dst in [*context.launch_configurations.get(REMAPS, []), *self.remappings]:
            ros_args += ["-r", f"{perform(context, src)}:={perform(context, dst)}"]
        ros_args += [perform(context, a) for a in self.ros_arguments]
        args = [perform(context, a) for a in self.arguments]
        label = perform(context, self.name) if self.name is not None else executable.rsplit("/", 1)[-1]
        if label.endswith(".py"):
            label = label[:-3]
        plan = ProcessPlan(
            self,
            label,
            program=found.program,
            entry=found.entry,
            args=[*args, "--ros-args", *ros_args] if ros_args else args,
            workspace=found.workspace,
            **self._common(context),
        )
        context.runner.start(plan, context)
        if self.on_exit is not None:
            from launch.event_handlers import OnProcessExit

            context.runner.register(OnProcessExit(target_action=self, on_exit=self.on_exit))

    def _parameters(self, context: LaunchContext, item: Any) -> list[str]:
        if isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):  # a global (name, value)
            item = {item[0]: item[1]}
        if isinstance(item, Parameter):
            item = {perform(context, item.name): ParameterValue(item.value, value_type=item.value_type)}
        if isinstance(item, ParameterFile):
            item = item.param_file
        if isinstance(item, dict):
            values = _value(context, item)
            text = yaml.safe_dump({"/**": {"ros__parameters": values}}, default_flow_style=False)
            return ["--params-file", str(context.runner.temp_file("params", ".yaml", text))]
        return ["--params-file", perform(context, item)]


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch_ros.actions", name, __all__)
