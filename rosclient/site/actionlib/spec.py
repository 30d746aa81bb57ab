"""An action's classes as actionlib's ActionSpec gives them: from `XAction` (the genmsg message
`from pkg.msg import XAction`) or the `.action` class (`from pkg.action import X`), its goal,
result and feedback messages and the three messages its topics carry."""

from __future__ import annotations

import importlib
from typing import Any


class ActionSpec:
    def __init__(self, action_class: Any) -> None:
        self.action_class = action_class
        self.Goal, self.Result, self.Feedback = action_class.Goal, action_class.Result, action_class.Feedback
        self.action_type: str = getattr(action_class, "_action_type", "") or action_class._type
        package, _, name = self.action_type.partition("/")
        name = name.rpartition("/")[2]
        msg = importlib.import_module(f"{package}.msg")
        self.ActionGoal = getattr(msg, f"{name}ActionGoal")
        self.ActionResult = getattr(msg, f"{name}ActionResult")
        self.ActionFeedback = getattr(msg, f"{name}ActionFeedback")
