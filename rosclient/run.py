"""`hri-lab run FILE.py [ARGS...] [--ros-args ...]` and `hri-lab run PKG EXE [ARGS...]`: a student's
ROS program against the lab, like `rosrun` / `ros2 run`. PKG EXE is a package's executable as
rosclient/executables.py finds it (an entry point of setup.py, or a file of the package). This
process becomes the program (rosclient/boot.py): its exit status, its signals (Ctrl+C ends
rospy.spin() / rclpy.spin()) and its output are the program's."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from rosclient import executables


def program_env(url: str, workspace: str | None) -> dict[str, str]:
    env = dict(os.environ, HRI_LAB_URL=url, PYTHONUNBUFFERED="1")
    if workspace:
        env[executables.WORKSPACE_ENV] = str(Path(workspace).resolve())
    return env


def command(program: str, args: list[str], entry: str | None = None) -> list[str]:
    return [sys.executable, "-m", "rosclient.boot", *(("--entry", entry) if entry else ()), program, *args]


def executable_command(found: executables.Executable, args: list[str]) -> list[str]:
    return command(str(found.program), args, found.entry)


def is_package_form(program: str, args: list[str]) -> bool:
    """`hri-lab run PKG EXE`: PKG is no file and names no .py file, and an EXE follows."""
    return (
        not Path(program).is_file()
        and not program.endswith(".py")
        and "/" not in program
        and bool(args)
        and not args[0].startswith("-")
    )


def run(args: argparse.Namespace) -> int:
    program = Path(args.program)
    workspace = args.workspace
    argv = list(args.args)
    entry = None
    if is_package_form(args.program, argv):
        roots = executables.workspaces(Path.cwd(), workspace)
        try:
            found = executables.resolve(args.program, argv[0], roots)
        except executables.NotFound as exc:
            print(exc, file=sys.stderr)
            return 1
        program, entry, argv = found.program, found.entry, argv[1:]
        workspace = str(found.workspace)
    elif not program.is_file():
        print(f"error: no program {program} (a package's executable: hri-lab run PKG EXE)", file=sys.stderr)
        return 2
    env = program_env(args.url, workspace)
    root = str(Path(__file__).resolve().parents[1])  # the lab's packages, whatever the working folder
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH", "")) if p)
    sys.stdout.flush()
    os.execve(sys.executable, command(str(program), argv, entry), env)
    return 0  # not reached
