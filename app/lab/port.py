"""The lab's port: what the API, the view, rosbridge and the lab's own helpers use of a running lab
(the lifting lab, app/lab/lab.py, or the mobile one, app/mobile/lab.py), as a typed Protocol, so
that they are handed this and not `Any`. `S` is the lab's snapshot type (sim.world.Snapshot,
sim.mobile.world.MobileSnapshot)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Protocol, TypeVar, runtime_checkable

from app.ros.param_tree import ParameterTree
from app.ros.params import ParameterServer
from app.ros.rosout import Rosout
from app.runtime.process import SimulationProcess

S_co = TypeVar("S_co", covariant=True)
T = TypeVar("T")


@runtime_checkable
class LabPort(Protocol[S_co]):
    """A running lab: its simulation (commands between two steps, the latest snapshot), its ROS
    registries (the node parameters, ROS 1's parameter tree, /rosout) and where its files go."""

    runtime: SimulationProcess  # the simulation's process (its health, restarts)
    rosout: Rosout
    params: ParameterServer
    param_tree: ParameterTree
    recordings_dir: Path
    figures_dir: Path

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
