"""`hri-lab run FILE.py [ARGS...] [--ros-args ...]`: a student's ROS program against the lab, like
`rosrun` / `ros2 run`. This process becomes the program (rosclient/boot.py): its exit status,
its signals (Ctrl+C ends rospy.spin() / rclpy.spin()) and its output are the program's."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path


def program_env(url: str, workspace: str | None) -> dict[str, str]:
    env = dict(os.environ, HRI_LAB_URL=url, PYTHONUNBUFFERED="1")
    if workspace:
        env["HRI_LAB_WORKSPACE"] = str(Path(workspace).resolve())
    return env


def command(program: str, args: list[str]) -> list[str]:
    return [sys.executable, "-m", "rosclient.boot", program, *args]


def run(args: argparse.Namespace) -> int:
    program = Path(args.program)
    if not program.is_file():
        print(f"error: no program {program}", file=sys.stderr)
        return 2
    env = program_env(args.url, args.workspace)
    root = str(Path(__file__).resolve().parents[1])  # the lab's packages, whatever the working folder
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH", "")) if p)
    sys.stdout.flush()
    os.execve(sys.executable, command(str(program), args.args), env)
    return 0  # not reached
