"""The composition root: the one place that builds the lab's parts and hands each what it needs.

`hri-lab serve` (app/cli/serve.py), `hri-lab wall-trial`, the docs' reference hook and the tests'
fixtures build the app here. Made once and handed down, never reached for: the lab (its
simulation, parameters and logs), the service registry with the nodes' services
(app/ros/node_services.py), the ActionServer with the nodes' actions (app/ros/node_actions.py),
the nodes' parameters behind the lab's parameter server (app/ros/node_params.py), the rosbridge
endpoint (app/rosbridge/endpoint.py), the HTTP API (app/api/app.py) and the 3D view (app/view/),
which runs while the app is served.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from fastapi import FastAPI
from starlette.datastructures import State

from sim.messages import Topic

from app.api.app import Running, create_api
from app.lab.actions import ACTIONS
from app.lab.events import LAB_NODE
from app.lab.lab import Lab
from app.lab.services import EXERCISES, NODE_EFFECTS, SERVICES
from app.lab.topics import TOPICS
from app.mobile.lab import MobileLab
from app.mobile.services import SERVICES as MOBILE_SERVICES
from app.ros.actions import Action, ActionServer
from app.ros.node_actions import NodeActions
from app.ros.node_params import NodeParameters
from app.ros.node_services import NodeServices
from app.rosbridge import endpoint as rosbridge
from app.tokens import token_problem


def create_app(
    lab: Lab | MobileLab | None = None,
    view: str = "none",
    view_host: str = "127.0.0.1",
    view_port: int = 8080,
    token: str | None = None,
    exercises: bool = False,
    replay: bool = False,
) -> FastAPI:
    """The app around `lab` (a new Lab if none); the simulation runs while the app is served.
    view: "full" (visual meshes), "light" (collision meshes, no shadows) or "none" (no 3D view).
    view_host: the address the server (API and view) is bound to; requests must name it
    (app/security.py). token: when set, state-changing requests must carry it (app/api/access.py).
    exercises: the handout's exercise services are left to the students' nodes (rosbridge).
    replay: the simulation publishes no topic over rosbridge: a bag played into the lab publishes them
    (app/rosbridge/managers/topics.py, docs/recording.md)."""
    if token and token_problem(token):
        raise ValueError(token_problem(token))
    parts = build(lab or Lab(), token, exercises, replay)
    lab = parts.lab
    maker = _view_maker(lab, parts.actions, parts.nodes, view, view_host, view_port, token)
    view_part = ViewPart(maker) if view != "none" else None
    app = create_api(
        lab,
        parts.nodes,
        parts.actions,
        parts.actions_declared,
        parts.topics_declared,
        lifting=parts.lifting,
        bound_host=view_host,
        token=token,
        running=[lab] if view_part is None else [lab, view_part],
        routers=[rosbridge.router(parts.bridge)],  # rosbridge v2: WebSocket at /
    )
    app.state.bridge = parts.bridge  # its programs' image windows: app/api/camera.py
    if view_part is not None:
        view_part.state = app.state
    return app


@dataclass(frozen=True)
class Parts:
    """The lab and what serves it, wired: what the API, rosbridge and the view are handed."""

    lab: Lab | MobileLab
    lifting: bool  # the lifting lab (else the mobile world: it declares topics only)
    nodes: NodeServices  # the declared services and the nodes'
    actions: ActionServer  # the declared actions and the nodes'
    actions_declared: list[Action]
    topics_declared: list[Topic]
    bridge: rosbridge.Bridge  # what every rosbridge client shares


def build(lab: Lab | MobileLab, token: str | None = None, exercises: bool = False, replay: bool = False) -> Parts:
    """The lab's registries, the nodes' parts of them and the rosbridge state, wired once."""
    lifting = not isinstance(lab, MobileLab)
    if isinstance(lab, MobileLab):
        services_declared, actions_declared, topics_declared = MOBILE_SERVICES, [], lab.topics
    else:
        services_declared, actions_declared, topics_declared = SERVICES, ACTIONS, TOPICS
    nodes = NodeServices(
        services_declared,
        lab,
        EXERCISES if exercises and lifting else (),
        effects=NODE_EFFECTS if lifting else None,
        caller=LAB_NODE,
    )
    actions = ActionServer(actions_declared, lab)
    lab.params.remote = NodeParameters(nodes)  # parameters nodes declare, in the same parameter server
    bridge = rosbridge.Bridge(lab, nodes, actions, NodeActions(actions), token, replay=replay)
    return Parts(lab, lifting, nodes, actions, actions_declared, topics_declared, bridge)


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


def _view_maker(
    lab: Lab | MobileLab,
    actions: ActionServer,
    nodes: NodeServices,
    view: str,
    host: str,
    port: int,
    token: str | None,
) -> Callable[[], Running]:
    """How to make the lab's 3D view (viser is imported only when a view is asked for)."""
    light = view == "light"
    if isinstance(lab, MobileLab):

        def mobile() -> Running:
            from app.view.mobile_view import MobileView

            return MobileView(lab, host, port, light=light)

        return mobile

    def lifting() -> Running:
        from app.view.view3d import LabView

        return LabView(lab, actions, nodes.registry, host, port, light=light, controls=token is None)

    return lifting
