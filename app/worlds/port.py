"""The lab's port: what the API, the view, rosbridge and the lab's own helpers use of a running lab
(any world's: the lifting lab, app/lab/lab.py, the mobile one, app/mobile/lab.py; what a world is:
app/worlds/contract.py), as a typed Protocol, so that they are handed this and not `Any`. `S` is
the lab's snapshot type (sim.world.Snapshot, sim.mobile.world.MobileSnapshot)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any, Protocol, TypeVar, runtime_checkable

from app.recording.services import Recorder
from app.ros.param_tree import ParameterTree
from app.ros.params import ParameterServer
from app.ros.rosout import Rosout
from app.runtime.camera_process import CameraProcess
from app.runtime.process import SimulationProcess

S_co = TypeVar("S_co", covariant=True)
T = TypeVar("T")


@runtime_checkable
class LabPort(Protocol[S_co]):
    """A running lab: its simulation (commands between two steps, the latest snapshot), its ROS
    registries (the node parameters, ROS 1's parameter tree, /rosout) and where its files go."""

    runtime: SimulationProcess[Any]  # the simulation's process (its health, restarts)
    rosout: Rosout
    params: ParameterServer
    param_tree: ParameterTree
    recordings_dir: Path
    figures_dir: Path
    # a graded trial's lab (app/grading/wall_trial.py): a client without the token is the graded program, a node as
    # on a robot; nothing may reset its world, and the world's grader topics are not served (World.served_topics)
    graded: bool

    @property
    def camera(self) -> CameraProcess | None:
        """Its camera, rendering /image_raw (app/runtime/camera_process.py), if it has one."""
        ...

    @property
    def recorder(self) -> Recorder | None:
        """Its live recording (app/recording/services.py), one at a time."""
        ...

    def start(self) -> None: ...

    def stop(self) -> None: ...

    def snapshot(self) -> S_co:
        """The latest published state of the world."""
        ...

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T:
        """fn(world, *args) run in the simulation between two steps; its result."""
        ...

    def submit(self, fn: Callable[..., T], *args: object) -> Future[T]:
        """fn(world, *args) sent to the simulation without waiting."""
        ...

    def needs(self, period: float, snapshots: bool = True) -> AbstractContextManager[None]:
        """While the block runs, a step every `period` s and, unless `snapshots` is false, a fresh
        snapshot as often."""
        ...

    def info(self, node: str, message: str) -> None:
        """One of the lab's log lines on /rosout (INFO)."""
        ...
