"""The composition root: the one place that builds the lab's parts and hands each what it needs,
for any world (what a world is: app/worlds/contract.py; which there are: app/serving/worlds.py).

`hri-lab serve` (app/cli/serve.py), `hri-lab wall-trial`, the docs' reference hook and the tests'
fixtures build the app here. Made once and handed down, never reached for: the world's lab (its
simulation, parameters and logs), the service registry with the nodes' services
(app/ros/node_services.py), the ActionServer with the nodes' actions (app/ros/node_actions.py),
the nodes' parameters behind the lab's parameter server (app/ros/node_params.py), the rosbridge
endpoint (app/rosbridge/endpoint.py), the HTTP API (app/api/app.py) and the world's 3D view,
which runs while the app is served.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from fastapi import FastAPI
from starlette.datastructures import State

from sim.messages import Topic

from app.api.app import create_api
from app.ros.actions import Action, ActionServer
from app.ros.names import LAB_NODE
from app.ros.node_actions import NodeActions
from app.ros.node_params import NodeParameters
from app.ros.node_services import NodeServices
from app.rosbridge import endpoint as rosbridge
from app.serving.worlds import DEFAULT, WORLDS
from app.tokens import token_problem
from app.worlds.contract import LabOptions, Running, ViewRequest, World
from app.worlds.port import LabPort


def create_app(
    world: World | None = None,
    lab: LabPort[Any] | None = None,
    view: str = "none",
    view_host: str = "127.0.0.1",
    view_port: int = 8080,
    token: str | None = None,
    exercises: bool = False,
    replay: bool = False,
) -> FastAPI:
    """The app around `lab`, a lab of `world` (the registry's default world if none: app/serving/worlds.py; a
    new lab if none); the simulation runs while the app is served.
    view: "full" (visual meshes), "light" (collision meshes, no shadows) or "none" (no 3D view).
    view_host: the address the server (API and view) is bound to; requests must name it
    (app/security.py). token: when set, state-changing requests must carry it (app/api/access.py).
    exercises: the handout's exercise services are left to the students' nodes (rosbridge).
    replay: the simulation publishes no topic over rosbridge: a bag played into the lab publishes them
    (app/rosbridge/managers/topics.py, docs/recording.md)."""
    if token and token_problem(token):
        raise ValueError(token_problem(token))
    world = world or WORLDS[DEFAULT]
    parts = build(world, lab or world.lab(LabOptions()), token, exercises, replay)
    lab = parts.lab
    request = ViewRequest(
        lab, parts.actions, parts.nodes.registry, view_host, view_port, view == "light", token is None
    )
    view_part = ViewPart(lambda: world.view(request)) if view != "none" else None
    app = create_api(
        lab,
        parts.nodes,
        parts.actions,
        parts.actions_declared,
        parts.topics_declared,
        world_routes=world.routes,
        bound_host=view_host,
        token=token,
        running=[lab] if view_part is None else [lab, view_part],
        routers=[rosbridge.router(parts.bridge)],  # rosbridge v2: WebSocket at /
    )
    app.state.world = world
    app.state.bridge = parts.bridge  # its programs' image windows: app/api/camera.py
    if view_part is not None:
        view_part.state = app.state
    return app


@dataclass(frozen=True)
class Parts:
    """The lab and what serves it, wired: what the API, rosbridge and the view are handed."""

    world: World
    lab: LabPort[Any]
    nodes: NodeServices  # the declared services and the nodes'
    actions: ActionServer  # the declared actions and the nodes'
    actions_declared: list[Action]
    topics_declared: list[Topic]  # the topics its lab serves (a graded trial's fewer)
    bridge: rosbridge.Bridge  # what every rosbridge client shares


def build(
    world: World, lab: LabPort[Any], token: str | None = None, exercises: bool = False, replay: bool = False
) -> Parts:
    """The lab's registries, the nodes' parts of them and the rosbridge state, wired once."""
    actions_declared, topics_declared = list(world.actions), world.served_topics(lab.graded)
    nodes = NodeServices(
        world.services,
        lab,
        world.exercises if exercises else (),
        effects=world.node_effects,
        caller=LAB_NODE,
    )
    actions = ActionServer(actions_declared, lab)
    lab.params.remote = NodeParameters(nodes)  # parameters nodes declare, in the same parameter server
    bridge = rosbridge.Bridge(world, lab, nodes, actions, NodeActions(actions), token, replay=replay)
    # HTTP serves each topic as rosbridge does: /tf and /tf_static with the programs' frames after the lab's
    topics_declared = [bridge.topics.lab_topic(t.name) or t for t in topics_declared]
    return Parts(world, lab, nodes, actions, actions_declared, topics_declared, bridge)


class ViewPart:
    """The 3D view, made when the app starts (after the lab: it draws the lab's first snapshot) and
    shown to the API (app.state.view: app/api/system.py, serve's banner)."""

    def __init__(self, make: Callable[[], Running]) -> None:
        self.make = make
        self.view: Running | None = None
        self.state: State | None = None  # the app's state, where the API finds the view

    def start(self) -> None:
        self.view = self.make()
        self.view.start()
        if self.state is not None:
            self.state.view = self.view

    def stop(self) -> None:
        if self.view is not None:
            self.view.stop()
        if self.state is not None:
            self.state.view = None
