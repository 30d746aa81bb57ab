"""The Panda placed from q in a viser scene, two ways: the lab's views (app/view/scene.py's
`RobotMeshes`: pinocchio's geometry placements) and viser's `ViserUrdf` over yourdfpy, as the URDF
view draws a robot (the same URDF, its gripper left out as the lab leaves it out). The CPU time of
the placing thread per placement, which other processes on a shared machine inflate less than
wall time (docs/design.md, "The 3D views").

    .venv/bin/python -m bench.robot_drawing [--placements 1000]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import viser

from sim.robot.assets import panda_urdf, robot_data_share
from sim.robot.panda import PandaModel

from app.view.scene import NOT_SHOWN, RobotMeshes


class ViserUrdfPanda:
    """viser's ViserUrdf drawing the Panda without its gripper (what the lab view would use)."""

    def __init__(self, server: viser.ViserServer, light: bool) -> None:
        import yourdfpy
        from viser.extras import ViserUrdf

        def package_path(fname: str) -> str:
            return (
                str(robot_data_share() / fname.removeprefix("package://")) if fname.startswith("package://") else fname
            )

        robot = yourdfpy.URDF.load(str(panda_urdf()), build_scene_graph=False, load_meshes=False).robot
        robot.links = [link for link in robot.links if not link.name.startswith(NOT_SHOWN)]
        robot.joints = [joint for joint in robot.joints if not joint.child.startswith(NOT_SHOWN)]
        urdf = yourdfpy.URDF(
            robot,
            build_scene_graph=not light,
            load_meshes=not light,
            build_collision_scene_graph=light,
            load_collision_meshes=light,
            filename_handler=package_path,
        )
        self.drawn = ViserUrdf(
            server, urdf, root_node_name="/viser_urdf", load_meshes=not light, load_collision_meshes=light
        )

    def place(self, q: np.ndarray) -> None:
        self.drawn.update_cfg(q)


def cpu_per_placement(robot, model: PandaModel, placements: int) -> list[float]:
    """The placing thread's CPU time (s) of each placement, along a path through the joint ranges."""
    times = []
    for k in range(placements):
        q = model.q_min + (model.q_max - model.q_min) * (0.5 + 0.4 * np.sin(0.01 * k + np.arange(model.nq)))
        started = time.thread_time()
        robot.place(q)
        times.append(time.thread_time() - started)
    return times


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--placements", type=int, default=1000)
    args = parser.parse_args()
    model = PandaModel()
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        for light in (False, True):
            for name, kind in (("pinocchio (RobotMeshes)", RobotMeshes), ("ViserUrdf", ViserUrdfPanda)):
                times = cpu_per_placement(kind(server, light), model, args.placements)
                print(
                    f"{'light' if light else 'full'} meshes, {name}: median {statistics.median(times) * 1e3:.2f} ms, "
                    f"mean {statistics.fmean(times) * 1e3:.2f} ms thread CPU per placement"
                )
    finally:
        server.stop()


if __name__ == "__main__":
    main()
