"""The Lab: the server's one simulation (in its own process, app/runtime), its parameters and its log."""

from collections.abc import Callable
from concurrent.futures import Future
from contextlib import AbstractContextManager
from typing import TypeVar

import numpy as np

from sim.camera_render import SceneSizes
from sim.controllers.interface import Controller
from sim.controllers.sp import SPController
from sim.robot.panda import PandaModel
from sim.world import Snapshot, World, WorldConfig

from app.lab.events import LabEvents
from app.lab.params import LAB_PARAMETERS
from app.lab.recorder import LiveRecorder
from app.lab.robot_description import ROBOT_DESCRIPTION, ROBOT_DESCRIPTION_WHY, robot_description_text
from app.recording.services import DEFAULT_DIR
from app.ros.names import LAB_NODE, node_name
from app.ros.param_tree import ParameterTree
from app.ros.params import ParameterServer
from app.ros.rosout import Rosout
from app.runtime.camera_process import CameraProcess
from app.runtime.process import SimulationProcess
from app.runtime.sample_ring import NewSamples

T = TypeVar("T")


class Lab:
    def __init__(
        self, config: WorldConfig | None = None, realtime: bool = True, controller: Controller | None = None
    ) -> None:
        self.world = World(
            config or WorldConfig(), controller or SPController()
        )  # the pristine one each process starts from
        self.runtime = SimulationProcess(self.world, realtime=realtime)
        self.camera = CameraProcess(self.runtime.snapshot, self._scene_sizes)  # /image_raw's renderer
        self.model = PandaModel()  # for computations on snapshots (not the simulation's pinocchio data)
        self.rosout = Rosout()  # /rosout: the lab's log lines and every node's
        self.events = LabEvents(self)  # logs reflexes, trials and restarts as they happen
        self.params = ParameterServer(LAB_PARAMETERS, self)  # the declared ROS 2 node parameters
        self.param_tree = ParameterTree(  # ROS 1's parameter server: any name (rosapi, rospy)
            read_only={ROBOT_DESCRIPTION: (robot_description_text(), ROBOT_DESCRIPTION_WHY)}
        )
        self.recordings_dir = DEFAULT_DIR  # where /start_recording writes (serve --output-dir DIR: DIR/recordings)
        self.figures_dir = DEFAULT_DIR.parent / "figures"  # the actions' figures (DIR/figures)
        self.recorder: LiveRecorder | None = None  # the live recording (app/lab/recorder.py), one at a time
        self.graded = False  # no trial of the lifting lab is graded live (its grading: app/grading/battery.py)

    def start(self) -> None:
        self.runtime.start()
        self.camera.start()
        self.info(node_name(LAB_NODE), "the simulation started")
        self.events.start()

    def stop(self) -> None:
        self.events.stop()
        if self.recorder is not None:  # a recording is finished (indexed) on shutdown
            self.recorder.stop()
        self.camera.stop()
        self.runtime.stop()

    def _scene_sizes(self) -> SceneSizes:
        """What the camera draws that does not move, from the world's configuration (m)."""
        cfg = self.world.config
        box, palm = cfg.box.size, cfg.palm_size
        return SceneSizes(
            (cfg.plate.width, cfg.plate.height, cfg.plate.offset), (box[0], box[1], box[2]), (palm[0], palm[1])
        )

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T:
        """Run fn(world, *args) in the simulation between two steps and return its result; fn is a
        function of app/lab/commands.py (sent by name)."""
        return self.runtime.call(fn, *args, timeout=timeout)

    def submit(self, fn: Callable[..., T], *args: object) -> Future[T]:
        """Send fn(world, *args) to the simulation without waiting (a stream of commands, e.g. a
        node's Twists); the future holds its result or its exception. fn as for `call`."""
        return self.runtime.submit(fn, *args)

    def snapshot(self) -> Snapshot:
        """The latest published state of the world."""
        return self.runtime.snapshot()

    def wrench_samples(self, seen: int) -> tuple[np.ndarray, int, int]:
        """Every step's (time, F_ext) after the first `seen` samples: (rows, new count, lost);
        app/runtime/sample_ring.py."""
        return self.runtime.wrenches.since(seen)

    def new_wrench_samples(self) -> AbstractContextManager[NewSamples]:
        """While the block runs, a waiter whose `next()` returns once a step has written its F_ext
        sample (app/runtime/sample_ring.py), in the running event loop."""
        return self.runtime.wrenches.new_samples()

    def needs(self, period: float, snapshots: bool = True) -> AbstractContextManager[None]:
        """While the block runs, a reader needs a step every `period` s (an idle loop wakes that
        often; app/runtime/loop.py) and, unless `snapshots` is false (a reader of every step's
        F_ext), a fresh snapshot as often."""
        return self.runtime.needs(period, snapshots)

    def info(self, node: str, message: str) -> None:
        """One of the lab's log lines on /rosout (level INFO)."""
        self.rosout.log(node, message)
