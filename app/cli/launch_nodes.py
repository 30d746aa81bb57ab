"""`hri-lab launch FILE` and `hri-lab launch PKG FILE`: an XML launch file's nodes run by
rosclient/launch.py, a Python or YAML one's by rosclient/pylaunch.py; without --url this starts the
lab for them first (`hri-lab serve --view none` in a session of its own, so Ctrl+C reaches the nodes,
and it is stopped after them, as roslaunch starts and stops its roscore)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from app.serving.launch import ServerProcess
from rosclient import launch, pylaunch


def run(args: argparse.Namespace) -> int:
    found = launch.target(args)
    if isinstance(found, str):
        print(f"error: {found}", file=sys.stderr)
        return 2
    path, arguments = found
    if args.workspace:  # $(find pkg) and <node pkg=...> resolve in it, as the nodes' imports do
        os.environ["HRI_LAB_WORKSPACE"] = str(Path(args.workspace).resolve())

    def start_lab() -> ServerProcess:
        return ServerProcess("--view", "none", own_session=True)

    if path.suffix == ".py":
        return pylaunch.run_file(path, arguments, args.url, args.workspace, start_lab)
    return launch.run(args, path, arguments, start_lab)
