"""What a world is: the one contract between a world's package (the lifting lab, app/lab/; the
mobile world, app/mobile/; a third: docs/design.md, "Adding a world") and the parts that serve any
world — the composition root (app/serving/compose.py), the HTTP API, rosbridge, the 3D view and the
recorder read a world only through this. A world's package declares one `World`; the registry
(app/serving/worlds.py) is the one place that names them.

A `World` is declarative: its simulation (how its lab is made, `lab`), its ROS vocabulary (topics,
services, actions, the exercises left to the students' nodes, what a node's answer does to it), the
topic a node's geometry_msgs/Twist drives its robot on and the command that follows it, its topics'
rates and latched ones, its 3D view, its own HTTP routes (its page and panels) and, when it has
one, its grader. A running lab is what app/worlds/port.py's LabPort says it is."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from fastapi import APIRouter

from sim.controllers.interface import Controller
from sim.messages import Topic

from app.ros.actions import Action, ActionServer
from app.ros.messages import RosMessage
from app.ros.services import ServiceRegistry
from app.worlds.port import LabPort

NodeEffect = Callable[[Any, RosMessage], None]  # (lab, request): what a node's answer of a service does to the lab
Command = Callable[[Any, Any], object]  # fn(sim world, twist [vx, vy, vz, wx, wy, wz]) run between two steps


class Running(Protocol):
    """What runs while the app is served (the lab's simulation, the 3D view): started in order,
    stopped in reverse."""

    def start(self) -> None: ...

    def stop(self) -> None: ...


@dataclass(frozen=True)
class LabOptions:
    """How `serve` (or a grader) asks for a world's lab; a world reads the options it knows."""

    controller: Controller | None = None  # the lifting controller (the lifting world's)
    config: Any = None  # the world's own configuration (its sim's), None: its default
    arena_seed: int | None = None  # a seeded arena (the mobile world's: `serve --arena-seed`)
    graded: bool = False  # a graded trial's lab (LabPort.graded)
    realtime: bool = True


@dataclass(frozen=True)
class ViewRequest:
    """What a world's 3D view is made with, once the app starts (viser imported only then)."""

    lab: LabPort[Any]
    actions: ActionServer
    services: ServiceRegistry
    host: str
    port: int
    light: bool  # collision meshes, no shadows
    controls: bool  # the view's buttons act on the lab (not when a token guards changes)


@dataclass(frozen=True)
class World:
    name: str  # `serve --world NAME`
    lab: Callable[[LabOptions], LabPort[Any]]  # its simulation: a new lab (not started)
    topics: Sequence[Topic]  # sampled from its snapshot (rosbridge, HTTP, its recording)
    services: ServiceRegistry  # its own services (the recording ones among them: app/recording/services.py)
    command_topic: str  # a node's geometry_msgs/Twist on it drives the robot
    command: Command  # what the lab runs with each of those Twists
    view: Callable[[ViewRequest], Running]  # its 3D view (`serve --view full|light`)
    actions: Sequence[Action] = ()
    exercises: tuple[str, ...] = ()  # `serve --exercises`: declared, left to the students' nodes
    node_effects: Mapping[str, NodeEffect] = field(default_factory=dict)
    min_period_s: Mapping[str, float] = field(default_factory=dict)  # at most this often to one subscriber (s)
    latched: frozenset[str] = frozenset()  # sent again only when the message changed (transient local)
    grader_topics: frozenset[str] = frozenset()  # not served to a graded trial's program (its ground truth)
    routes: Sequence[APIRouter] = ()  # its own HTTP routes: its page at / (else the lifting page), its panels
    warm_up: Callable[[LabPort[Any]], object] | None = None  # loads what its topics need, off the event loop
    grader: str = ""  # the command that grades programs in it, if any

    def served_topics(self, graded: bool) -> list[Topic]:
        """The topics its lab serves: all of them, but a graded trial's program sees what a node on
        the robot sees (not the grader's topics)."""
        return [t for t in self.topics if not (graded and t.name in self.grader_topics)]
