"""The starting files `hri-lab template` prints: the controller plug-in (sim/controllers/template.py)
and the nodes beside this file (roslibpy scripts, rospy and rclpy programs for `hri-lab run`).

A lifting node's `PARAMS = {}  # @lab-defaults` line is filled when the file is printed with the
lab's own /cooperative_lifting defaults (`LiftingParams`): one source, so a node a student starts
from always holds the lab's numbers (tests/app/cli/test_templates.py)."""

from __future__ import annotations

import importlib.util
from dataclasses import fields
from pathlib import Path

from sim.controllers.interface import LiftingParams
from sim.controllers.plugin import template_path

FILES = {  # (kind, api) -> the file beside this one
    ("services", "roslibpy"): "services_node.py",
    ("node", "roslibpy"): "lifting_node.py",
    ("services", "rospy"): "services_rospy.py",
    ("node", "rospy"): "lifting_rospy.py",
    ("services", "rclpy"): "services_rclpy.py",
    ("node", "rclpy"): "lifting_rclpy.py",
}
MARKER = "PARAMS = {}  # @lab-defaults"
# what the node's law uses: not the service's state (running, f_n_min) nor the rate limits, which
# the lab applies to a node's commands itself (libfranka's limit_rate)
NOT_IN_NODES = ("running", "f_n_min", "a_max", "dw_max")


def lab_defaults() -> dict[str, float]:
    """The lifting law's parameters a node uses, at the lab's defaults."""
    defaults = LiftingParams()
    return {f.name: float(getattr(defaults, f.name)) for f in fields(defaults) if f.name not in NOT_IN_NODES}


def _params_block(indent: str) -> str:
    lines = [f"{indent}PARAMS = {{  # the lab's /cooperative_lifting defaults (hri-lab template wrote them)"]
    lines += [f'{indent}    "{name}": {value!r},' for name, value in lab_defaults().items()]
    return "\n".join(lines + [f"{indent}}}"])


def render(kind: str, api: str = "rospy") -> str:
    """The text `hri-lab template KIND --api API` prints."""
    if kind == "controller":
        return template_path().read_text(encoding="utf-8")
    text = (Path(__file__).parent / FILES[kind, api]).read_text(encoding="utf-8")
    out = []
    for line in text.splitlines(keepends=True):
        stripped = line.strip()
        if stripped == MARKER:
            out.append(_params_block(line[: len(line) - len(line.lstrip())]) + "\n")
        else:
            out.append(line)
    rendered = "".join(out)
    if kind == "node" and rendered == text:
        raise RuntimeError(f"{FILES[kind, api]} has no '{MARKER}' line")
    return rendered
