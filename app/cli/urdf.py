"""`hri-lab urdf check FILE.urdf` (ROS's check_urdf) and `hri-lab urdf view FILE.urdf` (RViz with
joint_state_publisher_gui): a student's own URDF, checked by sim/robot/urdf_check.py, viewed by
app/view/urdf_view.py, its /joint_states and /robot_description served by app/view/urdf_bridge.py."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from app.cli.client import CliError

if TYPE_CHECKING:
    from sim.robot.urdf_check import UrdfModel


def _checked(path: str) -> UrdfModel:
    """The checked model (lxml imported here: the client commands start without it)."""
    from sim.robot.urdf_check import UrdfError, parse_urdf_file

    try:
        return parse_urdf_file(path)
    except UrdfError as error:
        raise CliError(error.located(path)) from None


def check(args) -> int:
    from sim.robot.urdf_check import joints_text, tree_text

    model = _checked(args.file)
    print(tree_text(model), end="")
    if not args.tree_only:
        print(joints_text(model), end="")
    return 0


def view(args) -> int:
    """The 3D view and its rosbridge server until Ctrl+C."""
    from pathlib import Path

    import uvicorn

    from app.serving.launch import free_port
    from app.view.urdf_bridge import urdf_app
    from app.view.urdf_view import UrdfView

    model = _checked(args.file)
    path = Path(args.file)
    try:
        view = UrdfView(path, model, port=args.view_port or free_port())
    except Exception as exc:  # noqa: BLE001 - yourdfpy/trimesh refusing what the check let through: one line
        raise CliError(f"{args.file}: cannot show it: {exc}") from None
    port = args.port or free_port()
    print(
        f"hri-lab urdf view: {model.name} ({path.name}), {len(view.sliders)} movable joint(s)\n"
        f"  3D view          {view.url}\n"
        f"  rosbridge        ws://127.0.0.1:{port}/  (/joint_states, /robot_description)\n"
        f"  joint states     hri-lab topic echo /joint_states --url http://127.0.0.1:{port}\n"
        "Press Ctrl+C to stop.",
        flush=True,
    )
    try:
        uvicorn.run(
            urdf_app(view.states, path.read_text(encoding="utf-8"), view.url),
            host="127.0.0.1",
            port=port,
            log_level="warning",
            access_log=False,
        )
    finally:
        view.stop()
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    urdf = sub.add_parser("urdf", help="check and view your own URDF (like check_urdf, and RViz with sliders)")
    urdf_sub = urdf.add_subparsers(dest="action", required=True)
    chk = urdf_sub.add_parser(
        "check",
        help="check a URDF as check_urdf does: its link tree, or the error with its line (exit 1)",
        description="Prints what ROS's check_urdf prints (the robot's name, the link tree), then the joints "
        "with their types and limits; an error is one line FILE:LINE: what is wrong and what was expected, exit 1.",
    )
    chk.add_argument("file", metavar="FILE.urdf")
    chk.add_argument("--tree-only", action="store_true", help="only what check_urdf prints (no joints list)")
    chk.set_defaults(func=check)
    viw = urdf_sub.add_parser(
        "view",
        help="show a URDF in the 3D view with a slider per movable joint; publish /joint_states",
        description="Checks the file (an error: exit 1), then serves the 3D view (a slider per movable joint, "
        "its limits from the file, a continuous joint +-pi; frames on request) and a rosbridge endpoint with "
        "/joint_states (sensor_msgs/JointState, 10 Hz and on every change) and the /robot_description parameter, "
        "both on 127.0.0.1, until Ctrl+C.",
    )
    viw.add_argument("file", metavar="FILE.urdf")
    viw.add_argument("--port", type=int, default=0, help="port of the rosbridge endpoint (default: a free one)")
    viw.add_argument("--view-port", type=int, default=0, help="port of the 3D view (default: a free one)")
    viw.set_defaults(func=view)


__all__ = ["add_parsers"]
