"""The mobile world's Lab (`hri-lab serve --world mobile`, docs/mobile-lab.md): the same runtime
as the lifting lab's (its own process, the loop, the shared snapshot: app/runtime), the same
ROS machinery (rosout, the node parameters, ROS 1's parameter tree) with the Burger's URDF; the
world's declarations (its topics, its command topic /cmd_vel, its recording services) are its
World's (app/mobile/world.py). It declares no parameters or actions of its own: the nodes that
run against it bring theirs."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import Future
from contextlib import AbstractContextManager
from typing import TypeVar

from sim.messages import Topic
from sim.mobile.urdf import burger_urdf
from sim.mobile.world import MobileConfig, MobileSnapshot, MobileWorld

from app.mobile.services import MobileRecorder
from app.mobile.topics import ROBOT_DESCRIPTION, TOPICS
from app.recording.services import DEFAULT_DIR
from app.ros.names import LAB_NODE, node_name
from app.ros.param_tree import ParameterTree
from app.ros.params import ParameterServer
from app.ros.rosout import Rosout
from app.runtime.process import SimulationProcess

T = TypeVar("T")


class MobileLab:
    def __init__(
        self,
        config: MobileConfig | None = None,
        realtime: bool = True,
        graded: bool = False,
        topics: Sequence[Topic] = TOPICS,
    ) -> None:
        self.topics = list(topics)  # what it serves, and records (app/mobile/world.py: a graded trial's fewer)
        self.world = MobileWorld(
            config
        )  # the pristine world each simulation process starts from (its arena, its figures)
        self.runtime = SimulationProcess(self.world, realtime=realtime)
        self.rosout = Rosout()
        self.params = ParameterServer([], self)  # nodes' parameters only (rosbridge sets `remote`)
        self.param_tree = ParameterTree(
            read_only={ROBOT_DESCRIPTION: (burger_urdf(), "the lab's robot, a TurtleBot3 Burger-like base")}
        )
        self.recordings_dir = DEFAULT_DIR
        self.figures_dir = DEFAULT_DIR.parent / "figures"
        self.camera = None  # no camera: no /image_raw
        self.recorder: MobileRecorder | None = None  # the live recording (app/mobile/services.py), one at a time
        # a graded trial (app/grading/wall_trial.py): nothing may reset its world, and its program sees what a
        # node on the robot sees: the grader's topics (the ground truth, the monitor) and the arena are not served
        self.graded = graded

    def start(self) -> None:
        self.runtime.start()
        self.info(node_name(LAB_NODE), "the simulation started (the mobile world)")

    def stop(self) -> None:
        if self.recorder is not None:  # a recording is finished (indexed) on shutdown
            self.recorder.stop()
        self.runtime.stop()

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T:
        """fn(world, *args) run in the simulation between two steps (fn: app/mobile/commands.py)."""
        return self.runtime.call(fn, *args, timeout=timeout)

    def submit(self, fn: Callable[..., T], *args: object) -> Future[T]:
        return self.runtime.submit(fn, *args)

    def snapshot(self) -> MobileSnapshot:
        return self.runtime.snapshot()

    def needs(self, period: float, snapshots: bool = True) -> AbstractContextManager[None]:
        return self.runtime.needs(period, snapshots)

    def info(self, node: str, message: str) -> None:
        self.rosout.log(node, message)
