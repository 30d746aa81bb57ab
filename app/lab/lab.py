"""The Lab: the server's one simulation (world + real-time loop in its own process), its
parameters and its log."""
import time
from collections import deque
from typing import Callable, TypeVar

from sim.controllers.interface import Controller
from sim.robot.panda import PandaModel
from sim.controllers.sp import SPController
from sim.world import Snapshot, World, WorldConfig

from app.ros.params import ParameterServer
from app.runtime.process import SimulationProcess

T = TypeVar("T")


class Lab:
    def __init__(self, config: WorldConfig | None = None, realtime: bool = True, controller: Controller | None = None) -> None:
        # the world the simulation process starts from (live state: snapshot() and call())
        self.world = World(config or WorldConfig(), controller or SPController())
        self.loop = SimulationProcess(self.world, realtime=realtime)
        self.model = PandaModel()  # for computations on snapshots (not the loop's pinocchio data)
        self.log: deque[dict] = deque(maxlen=200)  # what the services print (rosout)
        from app.lab.params import LAB_PARAMETERS

        self.params = ParameterServer(LAB_PARAMETERS, self)
        from app.lab.recorder import DEFAULT_DIR

        self.recordings_dir = DEFAULT_DIR  # where /start_recording writes (serve --output-dir DIR: DIR/recordings)
        self.figures_dir = DEFAULT_DIR.parent / "figures"  # the actions' figures (DIR/figures)
        self.recorder = None  # the live recording (app/lab/recorder.py), one at a time

    def start(self) -> None:
        self.loop.start()

    def stop(self) -> None:
        if self.recorder is not None:  # a recording is finished (indexed) on shutdown
            self.recorder.stop()
        self.loop.stop()

    def call(self, fn: Callable[..., T], *args, timeout: float = 10.0) -> T:
        """Run fn(world, *args) in the simulation between two steps and return its result; fn is
        sent by name (a function of app/world_commands.py or a method of World)."""
        return self.loop.call(fn, *args, timeout=timeout)

    def snapshot(self) -> Snapshot:
        return self.loop.snapshot()

    def info(self, node: str, message: str) -> None:
        """A log line (like rosout)."""
        self.log.append({"stamp": time.time(), "node": node, "level": "INFO", "msg": message})
