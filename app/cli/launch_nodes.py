"""`hri-lab launch FILE`: app/rosclient/launch.py runs the launch file's nodes; without --url this
starts the lab for them first (`hri-lab serve --view none` in a session of its own, so Ctrl+C
reaches the nodes, and it is stopped after them, as roslaunch starts and stops its roscore)."""

from __future__ import annotations

import argparse

from app.cli.launch import ServerProcess
from app.rosclient import launch, pylaunch


def run(args: argparse.Namespace) -> int:
    return launch.run(args, start_lab=lambda: ServerProcess("--view", "none", own_session=True), python=pylaunch.main)
