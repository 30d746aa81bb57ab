"""A declared range's rule, as rclcpp refuses a parameter set: a finite value from low to high.
The parameter server (app/ros/params.py) and the lifting parameters a plug-in's start()/stop()
write (sim/controllers/interface.py, `lifting_refusal`) both check with it."""

from __future__ import annotations

import math


def range_refusal(name: str, value: float, low: float, high: float, kind: str = "floating point") -> str:
    """rclcpp's reason for refusing `value` for parameter `name` declared from low to high; '' when it complies."""
    if math.isfinite(value) and low <= value <= high:
        return ""
    return f"Parameter {{{name}}} doesn't comply with {kind} range."
