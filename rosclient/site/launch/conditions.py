"""launch.conditions: whether an action is done."""

from __future__ import annotations

from typing import Any

from launch._core import Condition, LaunchContext, SubstitutionFailure, normalize, perform, refuse

__all__ = ["Condition", "IfCondition", "LaunchConfigurationEquals", "LaunchConfigurationNotEquals", "UnlessCondition"]


def evaluate_condition_expression(context: LaunchContext, expression: Any) -> bool:
    text = perform(context, expression).strip().lower()
    if text in ("true", "1"):
        return True
    if text in ("false", "0"):
        return False
    raise SubstitutionFailure(f"condition {text!r} is not a boolean: true, false, 1 or 0")


class IfCondition(Condition):
    def __init__(self, predicate_expression: Any) -> None:
        super().__init__()
        self.expression = normalize(predicate_expression)

    def evaluate(self, context: LaunchContext) -> bool:
        return evaluate_condition_expression(context, self.expression)


class UnlessCondition(IfCondition):
    def evaluate(self, context: LaunchContext) -> bool:
        return not evaluate_condition_expression(context, self.expression)


class LaunchConfigurationEquals(Condition):
    def __init__(self, launch_configuration_name: str, expected_value: Any) -> None:
        super().__init__()
        self.name = launch_configuration_name
        self.expected = None if expected_value is None else normalize(expected_value)

    def evaluate(self, context: LaunchContext) -> bool:
        value = context.launch_configurations.get(self.name)
        expected = None if self.expected is None else perform(context, self.expected)
        return value == expected


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


def __getattr__(name: str) -> Any:
    if name.startswith("__"):
        raise AttributeError(name)
    raise refuse("launch.conditions", name, __all__)
