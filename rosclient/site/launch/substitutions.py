"""launch.substitutions: text computed when the description is performed."""

from __future__ import annotations

import math
import os
import shlex
import shutil
import subprocess
from typing import Any

from launch._core import LaunchContext, Substitution, SubstitutionFailure, normalize, perform, refuse

__all__ = [
    "AndSubstitution",
    "Command",
    "EnvironmentVariable",
    "EqualsSubstitution",
    "FindExecutable",
    "LaunchConfiguration",
    "LocalSubstitution",
    "NotEqualsSubstitution",
    "NotSubstitution",
    "OrSubstitution",
    "PathJoinSubstitution",
    "PythonExpression",
    "Substitution",
    "SubstitutionFailure",
    "TextSubstitution",
    "ThisLaunchFile",
    "ThisLaunchFileDir",
]


class TextSubstitution(Substitution):
    def __init__(self, *, text: str = "") -> None:
        self.text = str(text)

    def perform(self, context: LaunchContext) -> str:
        return self.text


class LaunchConfiguration(Substitution):
    def __init__(self, variable_name: Any, *, default: Any = None) -> None:
        self.variable_name = normalize(variable_name)
        self.default = None if default is None else normalize(default)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.variable_name)
        if name in context.launch_configurations:
            value = context.launch_configurations[name]
            return value if isinstance(value, str) else str(value)
        if self.default is not None:
            return perform(context, self.default)
        raise SubstitutionFailure(f"launch configuration '{name}' does not exist")

    def __getitem__(self, key: Any) -> Any:
        raise refuse("launch.substitutions", "LaunchConfiguration[...]", __all__)


class EnvironmentVariable(Substitution):
    def __init__(self, name: Any, *, default_value: Any = None) -> None:
        self.name = normalize(name)
        self.default_value = None if default_value is None else normalize(default_value)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        if name in context.environment:
            return context.environment[name]
        if self.default_value is None:
            raise SubstitutionFailure(f"environment variable '{name}' does not exist")
        return perform(context, self.default_value)


class PathJoinSubstitution(Substitution):
    def __init__(self, substitutions: Any) -> None:
        self.substitutions = list(substitutions)

    def perform(self, context: LaunchContext) -> str:
        return os.path.join(*(perform(context, s) for s in self.substitutions)) if self.substitutions else ""

    def __truediv__(self, other: Any) -> PathJoinSubstitution:
        return PathJoinSubstitution([*self.substitutions, other])


class PythonExpression(Substitution):
    """Python's eval of the joined text, with math's names (launch's own rule)."""

    def __init__(self, expression: Any, python_modules: Any = ("math",)) -> None:
        self.expression = normalize(expression)
        self.modules = [m for m in normalize(python_modules) if isinstance(m, str)]

    def perform(self, context: LaunchContext) -> str:
        text = perform(context, self.expression)
        names: dict[str, Any] = {}
        if "math" in self.modules:
            names.update({k: getattr(math, k) for k in dir(math) if not k.startswith("_")})
        for module in self.modules:
            names[module] = __import__(module)
        try:
            return str(eval(text, names))  # noqa: S307 - launch's PythonExpression is eval, by definition
        except Exception as exc:
            raise SubstitutionFailure(f"PythonExpression {text!r}: {type(exc).__name__}: {exc}") from None


class LocalSubstitution(Substitution):
    """A local of the context (an event handler's `event`), by a dotted path: 'event.pid'."""

    def __init__(self, expression: str, *, description: str | None = None) -> None:
        self.expression = expression

    def perform(self, context: LaunchContext) -> str:
        head, *rest = self.expression.split(".")
        if not hasattr(context.locals, head):
            raise SubstitutionFailure(f"local '{head}' does not exist (only an event handler's actions have 'event')")
        value: Any = getattr(context.locals, head)
        for part in rest:
            value = getattr(value, part)
        return str(value)


class FindExecutable(Substitution):
    def __init__(self, *, name: Any) -> None:
        self.name = normalize(name)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        found = shutil.which(name, path=context.environment.get("PATH"))
        if found is None:
            if name in ("ros2", "rosrun", "roslaunch", "rosservice", "rostopic", "rosparam"):
                return name  # the runner gives these to hri-lab
            raise SubstitutionFailure(f"executable '{name}' not found on the PATH")
        return found


class ThisLaunchFileDir(Substitution):
    def perform(self, context: LaunchContext) -> str:
        if not context.files:
            raise SubstitutionFailure("ThisLaunchFileDir used outside a launch file")
        return str(context.files[-1].parent)


class ThisLaunchFile(Substitution):
    def perform(self, context: LaunchContext) -> str:
        if not context.files:
            raise SubstitutionFailure("ThisLaunchFile used outside a launch file")
        return str(context.files[-1])


class Command(Substitution):
    """The standard output of a command (shlex-split; launch's `Command`, e.g. xacro)."""

    def __init__(self, command: Any, *, on_stderr: str = "fail") -> None:
        self.command = normalize(command)
        self.on_stderr = on_stderr

    def perform(self, context: LaunchContext) -> str:
        text = perform(context, self.command)
        try:
            done = subprocess.run(
                shlex.split(text), capture_output=True, text=True, env=context.environment, timeout=60, check=False
            )
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise SubstitutionFailure(f"Command {text!r}: {exc}") from None
        if done.returncode != 0 or (done.stderr and self.on_stderr == "fail"):
            raise SubstitutionFailure(f"Command {text!r} failed: {done.stderr.strip() or done.returncode}")
        return done.stdout


def _truth(text: str, what: str) -> bool:
    lowered = text.strip().lower()
    if lowered in ("true", "1"):
        return True
    if lowered in ("false", "0"):
        return False
    raise SubstitutionFailure(f"{what}: {text!r} is not a boolean (true, false, 1, 0)")


class NotSubstitution(Substitution):
    def __init__(self, value: Any) -> None:
        self.value = normalize(value)

    def perform(self, context: LaunchContext) -> str:
        return str(not _truth(perform(context, self.value), "NotSubstitution")).lower()


class AndSubstitution(Substitution):
    def __init__(self, left: Any, right: Any) -> None:
        self.left, self.right = normalize(left), normalize(right)

    def perform(self, context: LaunchContext) -> str:
        left = _truth(perform(context, self.left), "AndSubstitution")
        return str(left and _truth(perform(context, self.right), "AndSubstitution")).lower()


class OrSubstitution(Substitution):
    def __init__(self, left: Any, right: Any) -> None:
        self.left, self.right = normalize(left), normalize(right)

    def perform(self, context: LaunchContext) -> str:
        left = _truth(perform(context, self.left), "OrSubstitution")
        return str(left or _truth(perform(context, self.right), "OrSubstitution")).lower()


class EqualsSubstitution(Substitution):
    def __init__(self, left: Any, right: Any) -> None:
        self.left, self.right = normalize(left), normalize(right)

    def perform(self, context: LaunchContext) -> str:
        return str(perform(context, self.left) == perform(context, self.right)).lower()


class NotEqualsSubstitution(EqualsSubstitution):
    def perform(self, context: LaunchContext) -> str:
        return str(perform(context, self.left) != perform(context, self.right)).lower()


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.substitutions", name, __all__)
