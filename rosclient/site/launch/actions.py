"""launch.actions: what a launch description does."""

from __future__ import annotations

import os
import shlex
from typing import Any

from launch._core import (
    Action,
    LaunchContext,
    LaunchDescription,
    LaunchDescriptionEntity,
    LaunchError,
    ProcessPlan,
    normalize,
    perform,
    refuse,
)
from launch.events import Shutdown as ShutdownEvent

__all__ = [
    "AppendEnvironmentVariable",
    "DeclareLaunchArgument",
    "EmitEvent",
    "ExecuteProcess",
    "GroupAction",
    "IncludeLaunchDescription",
    "LogInfo",
    "OpaqueFunction",
    "PopEnvironment",
    "PopLaunchConfigurations",
    "PushEnvironment",
    "PushLaunchConfigurations",
    "RegisterEventHandler",
    "SetEnvironmentVariable",
    "SetLaunchConfiguration",
    "Shutdown",
    "TimerAction",
    "UnregisterEventHandler",
    "UnsetEnvironmentVariable",
    "UnsetLaunchConfiguration",
]


class DeclareLaunchArgument(Action):
    """A launch argument: the value given (`name:=value`, an include's launch_arguments), else its
    default; none of the two is an error naming it, as launch says it."""

    def __init__(
        self, name: str, *, default_value: Any = None, description: str | None = None, choices: Any = None, **kwargs
    ) -> None:
        super().__init__(**kwargs)
        self.name = name
        self.default_value = None if default_value is None else normalize(default_value)
        self.description = description or "no description given"
        self.choices = list(choices) if choices is not None else None

    def declared_arguments(self) -> list[Any]:
        return [self]

    def execute(self, context: LaunchContext) -> None:
        if self.name not in context.launch_configurations:
            if self.default_value is None:
                given = sorted(context.launch_configurations)
                raise LaunchError(
                    f"Included launch description missing required argument '{self.name}' (description: "
                    f"'{self.description}'), given: [{', '.join(given)}]"
                )
            context.launch_configurations[self.name] = perform(context, self.default_value)
        value = context.launch_configurations[self.name]
        if self.choices is not None and value not in self.choices:
            raise LaunchError(
                f"Argument '{self.name}' provided value '{value}' is not valid. Valid options are: {self.choices}"
            )


class SetLaunchConfiguration(Action):
    def __init__(self, name: Any, value: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)

    def execute(self, context: LaunchContext) -> None:
        context.launch_configurations[perform(context, self.name)] = perform(context, self.value)


class UnsetLaunchConfiguration(Action):
    def __init__(self, name: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name = normalize(name)

    def execute(self, context: LaunchContext) -> None:
        context.launch_configurations.pop(perform(context, self.name), None)


class PushLaunchConfigurations(Action):
    def execute(self, context: LaunchContext) -> None:
        context.push()


class PopLaunchConfigurations(Action):
    def execute(self, context: LaunchContext) -> None:
        context.pop()


PushEnvironment, PopEnvironment = PushLaunchConfigurations, PopLaunchConfigurations


class SetEnvironmentVariable(Action):
    def __init__(self, name: Any, value: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)

    def execute(self, context: LaunchContext) -> None:
        context.environment[perform(context, self.name)] = perform(context, self.value)


class AppendEnvironmentVariable(Action):
    def __init__(self, name: Any, value: Any, *, prepend: Any = False, separator: Any = os.pathsep, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name, self.value, self.prepend, self.separator = name, value, prepend, separator

    def execute(self, context: LaunchContext) -> None:
        name, value = perform(context, self.name), perform(context, self.value)
        old = context.environment.get(name)
        prepend = self.prepend if isinstance(self.prepend, bool) else perform(context, self.prepend) == "true"
        sep = perform(context, self.separator)
        context.environment[name] = value if not old else (value + sep + old if prepend else old + sep + value)


class UnsetEnvironmentVariable(Action):
    def __init__(self, name: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.name = normalize(name)

    def execute(self, context: LaunchContext) -> None:
        context.environment.pop(perform(context, self.name), None)


class LogInfo(Action):
    def __init__(self, *, msg: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.msg = normalize(msg)

    def execute(self, context: LaunchContext) -> None:
        context.runner.log("INFO", "launch.user", perform(context, self.msg))


class GroupAction(Action):
    """Its actions, with launch configurations (and launch_ros's namespace) scoped to them unless
    scoped=False; `launch_configurations` set for them."""

    def __init__(
        self,
        actions: Any,
        *,
        scoped: bool = True,
        forwarding: bool = True,
        launch_configurations: dict | None = None,
        **kwargs,
    ) -> None:
        super().__init__(**kwargs)
        self.actions = list(actions)
        self.scoped = scoped
        self.forwarding = forwarding
        self.launch_configurations = dict(launch_configurations or {})

    def describe_sub_entities(self) -> list[LaunchDescriptionEntity]:
        return list(self.actions)

    def declared_arguments(self) -> list[Any]:
        return [argument for action in self.actions for argument in action.declared_arguments()]

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        sets: list[LaunchDescriptionEntity] = [
            SetLaunchConfiguration(k, v) for k, v in self.launch_configurations.items()
        ]
        if not self.scoped:
            return [*sets, *self.actions]
        keep = [] if self.forwarding else [_ClearConfigurations()]
        return [PushLaunchConfigurations(), *keep, *sets, *self.actions, PopLaunchConfigurations()]


class _ClearConfigurations(Action):
    def execute(self, context: LaunchContext) -> None:
        context.launch_configurations = {
            k: v for k, v in context.launch_configurations.items() if k.startswith("ros_") or k == "global_params"
        }


class IncludeLaunchDescription(Action):
    """Another launch file's description, its arguments set first (they stay set after it, as in
    launch: a GroupAction scopes them)."""

    def __init__(self, launch_description_source: Any, *, launch_arguments: Any = None, **kwargs) -> None:
        super().__init__(**kwargs)
        if isinstance(launch_description_source, str | list) or hasattr(launch_description_source, "perform"):
            from launch.launch_description_sources import AnyLaunchDescriptionSource

            launch_description_source = AnyLaunchDescriptionSource(launch_description_source)
        self.launch_description_source = launch_description_source
        if isinstance(launch_arguments, dict):
            launch_arguments = list(launch_arguments.items())
        self.launch_arguments = list(launch_arguments or [])

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        for key, value in self.launch_arguments:
            context.launch_configurations[perform(context, key)] = perform(context, value)
        described = self.launch_description_source.get_launch_description(context)
        path = self.launch_description_source.path(context)
        return [_EnterFile(path), described, _LeaveFile()]


class _EnterFile(Action):
    def __init__(self, path: Any) -> None:
        super().__init__()
        self.path = path

    def execute(self, context: LaunchContext) -> None:
        context.files.append(self.path)


class _LeaveFile(Action):
    def execute(self, context: LaunchContext) -> None:
        if context.files:
            context.files.pop()


class OpaqueFunction(Action):
    def __init__(self, *, function: Any, args: Any = None, kwargs: Any = None, **more) -> None:
        super().__init__(**more)
        self.function, self.args, self.kwargs = function, list(args or []), dict(kwargs or {})

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        result = self.function(context, *self.args, **self.kwargs)
        return list(result) if result else None


class TimerAction(Action):
    """Its actions `period` seconds later, with the launch configurations of now."""

    def __init__(self, *, period: Any, actions: Any, cancel_on_shutdown: bool = True, **kwargs) -> None:
        super().__init__(**kwargs)
        self.period, self.actions, self.cancel_on_shutdown = period, list(actions), cancel_on_shutdown

    def execute(self, context: LaunchContext) -> None:
        period = self.period if isinstance(self.period, int | float) else float(perform(context, self.period))
        context.runner.later(float(period), self.actions, context.snapshot(), self)

    def cancel(self) -> None:
        self.canceled = True


class RegisterEventHandler(Action):
    def __init__(self, event_handler: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.event_handler = event_handler

    def execute(self, context: LaunchContext) -> None:
        context.runner.register(self.event_handler)


class UnregisterEventHandler(RegisterEventHandler):
    def execute(self, context: LaunchContext) -> None:
        context.runner.unregister(self.event_handler)


class EmitEvent(Action):
    def __init__(self, *, event: Any, **kwargs) -> None:
        super().__init__(**kwargs)
        self.event = event

    def execute(self, context: LaunchContext) -> None:
        context.runner.emit(self.event)


class Shutdown(EmitEvent):
    def __init__(self, *, reason: str = "reason not given", **kwargs) -> None:
        super().__init__(event=ShutdownEvent(reason=reason), **kwargs)


class ExecuteProcess(Action):
    """A command, started by the runner (ros2/rosrun/roslaunch commands as hri-lab's)."""

    def __init__(
        self,
        *,
        cmd: Any,
        name: Any = None,
        cwd: Any = None,
        env: dict | None = None,
        additional_env: dict | None = None,
        shell: bool = False,
        output: Any = "log",
        sigterm_timeout: Any = 5.0,
        sigkill_timeout: Any = 5.0,
        respawn: Any = False,
        respawn_delay: float | None = None,
        emulate_tty: bool = False,
        prefix: Any = None,
        on_exit: Any = None,
        log_cmd: bool = False,
        cached_output: bool = False,
        respawn_max_retries: int = -1,
        **kwargs,
    ) -> None:
        super().__init__(**kwargs)
        self.cmd = list(cmd) if isinstance(cmd, list | tuple) else [cmd]
        self.name, self.cwd, self.env, self.additional_env = name, cwd, env, additional_env
        self.shell, self.output = shell, output
        self.sigterm_timeout = sigterm_timeout
        self.respawn, self.respawn_delay = respawn, respawn_delay or 0.0
        self.prefix = prefix
        self.on_exit = on_exit
        self.process_details: dict[str, Any] | None = None

    def _environment(self, context: LaunchContext) -> dict[str, str]:
        env = (
            {perform(context, k): perform(context, v) for k, v in self.env.items()}
            if self.env is not None
            else dict(context.environment)
        )
        for key, value in (self.additional_env or {}).items():
            env[perform(context, key)] = perform(context, value)
        return env

    def _common(self, context: LaunchContext) -> dict[str, Any]:
        output = perform(context, self.output) if not isinstance(self.output, str) else self.output
        respawn = self.respawn if isinstance(self.respawn, bool) else perform(context, self.respawn) == "true"
        timeout = self.sigterm_timeout
        return {
            "env": self._environment(context),
            "cwd": perform(context, self.cwd) if self.cwd is not None else None,
            "output": output,
            "respawn": respawn,
            "respawn_delay": float(self.respawn_delay),
            "sigterm_timeout": float(timeout if isinstance(timeout, int | float) else perform(context, timeout)),
        }

    def execute(self, context: LaunchContext) -> None:
        argv = [perform(context, part) for part in self.cmd]
        if self.shell and len(argv) > 1:
            argv = [" ".join(argv)]
        elif not self.shell and len(argv) == 1 and " " in argv[0]:
            argv = shlex.split(argv[0])
        if self.prefix is not None:
            argv = [*shlex.split(perform(context, self.prefix)), *argv]
        label = perform(context, self.name) if self.name is not None else os.path.basename(argv[0].split(" ")[0])
        plan = ProcessPlan(self, label, argv=argv, shell=self.shell, **self._common(context))
        context.runner.start(plan, context)
        if self.on_exit is not None:
            from launch.event_handlers import OnProcessExit

            context.runner.register(OnProcessExit(target_action=self, on_exit=self.on_exit))


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.actions", name, __all__)


_ = LaunchDescription  # re-exported by launch
