"""A world is a plug-in (app/worlds/contract.py): both registered worlds are what the contract says a
world is and the composition root builds either from it alone; a third world, declared here in a few
lines (a point on a line that follows a Twist's linear.x), is registered with one line and served
through the composition root — its topic over HTTP and rosbridge, its command topic driving it, its
own route — without a change anywhere else."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import Future
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any, TypeVar

import pytest
from fastapi import APIRouter, Request
from fastapi.testclient import TestClient

from sim.messages import Topic

from app.recording.services import DEFAULT_DIR
from app.ros.param_tree import ParameterTree
from app.ros.params import ParameterServer
from app.ros.rosout import Rosout
from app.ros.services import ServiceRegistry
from app.runtime.process import SimulationProcess
from app.serving.compose import build, create_app
from app.serving.worlds import DEFAULT, WORLDS
from app.worlds.contract import LabOptions, Running, ViewRequest, World
from app.worlds.port import LabPort
from tests.waiting import wait_for

T = TypeVar("T")


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_a_registered_world_is_the_contract_and_compose_builds_it(name):
    world = WORLDS[name]
    assert isinstance(world, World) and world.name == name
    lab = world.lab(LabOptions(realtime=False))  # not started: no process runs
    assert isinstance(lab, LabPort)
    parts = build(world, lab, replay=False)
    assert parts.world is world and parts.lab is lab
    assert [t.name for t in parts.topics_declared] == [t.name for t in world.topics]
    assert set(parts.bridge.topics.sampled_names()) == {t.name for t in world.topics}
    assert parts.bridge.topics.command_topic == world.command_topic
    assert parts.bridge.topics.command is world.command
    assert parts.bridge.topics.min_period_s == dict(world.min_period_s)
    assert set(parts.bridge.topics.latched) == set(world.latched)
    assert {s.name for s in world.services} <= {s.name for s in parts.nodes.registry}
    assert [a.name for a in parts.actions_declared] == [a.name for a in world.actions]


def test_the_default_world_is_registered_and_a_graded_lab_serves_no_grader_topic():
    assert DEFAULT in WORLDS
    graded = [w for w in WORLDS.values() if w.grader_topics]
    assert graded, "a registered world hides topics from a graded program"
    for world in graded:
        lab = world.lab(LabOptions(realtime=False, graded=True))
        parts = build(world, lab)
        assert lab.graded and parts.bridge.graded
        assert not {t.name for t in parts.topics_declared} & world.grader_topics
        assert not set(parts.bridge.topics.sampled_names()) & world.grader_topics


# --- a third world, declared in this file ------------------------------------------------------
POSITION = "/point/position"
COMMAND = "/point/cmd_vel"


@dataclasses.dataclass(frozen=True)
class PointConfig:
    dt: float = 0.001  # s per step


@dataclasses.dataclass
class PointSnapshot:
    time: float
    x: float  # m along the line
    error: str | None = None


class PointWorld:
    """A point on a line, at the commanded speed (m/s)."""

    def __init__(self) -> None:
        self.config = PointConfig()
        self.time, self.x, self.speed, self.error = 0.0, 0.0, 0.0, None

    @property
    def commanded(self) -> bool:
        return self.speed != 0.0

    def step(self) -> None:
        self.time += self.config.dt
        self.x += self.speed * self.config.dt

    def snapshot(self) -> PointSnapshot:
        return PointSnapshot(self.time, self.x, self.error)

    def fail(self, reason: str) -> None:
        self.error = reason


def follow(world: PointWorld, twist: list[float]) -> None:
    world.speed = float(twist[0])


class PointLab:
    def __init__(self, options: LabOptions) -> None:
        self.runtime = SimulationProcess(PointWorld(), realtime=options.realtime)
        self.rosout = Rosout()
        self.params = ParameterServer([], self)
        self.param_tree = ParameterTree()
        self.recordings_dir: Path = DEFAULT_DIR
        self.figures_dir: Path = DEFAULT_DIR.parent / "figures"
        self.graded = options.graded
        self.camera = None
        self.recorder = None

    def start(self) -> None:
        self.runtime.start()

    def stop(self) -> None:
        self.runtime.stop()

    def snapshot(self) -> PointSnapshot:
        return self.runtime.snapshot()

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T:
        return self.runtime.call(fn, *args, timeout=timeout)

    def submit(self, fn: Callable[..., T], *args: object) -> Future[T]:
        return self.runtime.submit(fn, *args)

    def needs(self, period: float, snapshots: bool = True) -> AbstractContextManager[None]:
        return self.runtime.needs(period, snapshots)

    def info(self, node: str, message: str) -> None:
        self.rosout.log(node, message)


def no_view(request: ViewRequest) -> Running:
    raise AssertionError("the point world is served without a view")


panel = APIRouter(tags=["point"])


@panel.get("/point", summary="Where the point is")
def where(request: Request) -> dict:
    return {"x": request.app.state.lab.snapshot().x}


POINT = World(
    name="point",
    lab=PointLab,
    topics=[Topic(POSITION, "std_msgs/Float64", lambda s: {"data": s.x})],
    services=ServiceRegistry([]),
    command_topic=COMMAND,
    command=follow,
    view=no_view,
    min_period_s={POSITION: 0.01},
    routes=(panel,),
)


def test_a_third_world_is_registered_with_one_line_and_served_through_compose(monkeypatch):
    monkeypatch.setitem(WORLDS, POINT.name, POINT)  # its registration line
    lab: Any = POINT.lab(LabOptions())
    assert isinstance(lab, LabPort)
    with TestClient(create_app(WORLDS["point"], lab)) as client:
        assert {"name": POSITION, "type": "std_msgs/Float64"} in client.get("/topics").json()
        assert client.get("/point").json() == {"x": 0.0}
        with client.websocket_connect("/") as ros:
            ros.send_json({"op": "call_service", "service": "/rosapi/topics", "id": "t"})
            assert POSITION in ros.receive_json()["values"]["topics"]
            ros.send_json({"op": "advertise", "topic": COMMAND, "type": "geometry_msgs/Twist"})
            twist = {"linear": {"x": 1.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}

            def moved() -> bool:
                ros.send_json({"op": "publish", "topic": COMMAND, "msg": twist})
                return client.get("/topics" + POSITION).json()["data"] > 0.0

            wait_for(moved)
            ros.send_json({"op": "subscribe", "topic": POSITION, "id": "p"})
            message = ros.receive_json()
            assert message["op"] == "publish" and message["topic"] == POSITION and message["msg"]["data"] > 0.0
        assert client.get("/point").json()["x"] > 0.0
