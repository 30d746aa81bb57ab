"""The lifting world as a world is declared (app/worlds/contract.py): the Panda's lab (app/lab/lab.py)
with its topics, services, actions and parameters, its command topic (a node's Twist in the base
frame), its 3D view (app/lab/view.py) and its own routes (teleop, the robot's model, the camera)."""

from __future__ import annotations

from sim.world import Snapshot

from app.api import camera as camera_api
from app.lab import commands, robot_routes, teleop
from app.lab.actions import ACTIONS
from app.lab.lab import Lab
from app.lab.services import EXERCISES, NODE_EFFECTS, SERVICES
from app.lab.topics import LATCHED, MIN_PERIOD_S, TOPICS, franka_state
from app.worlds.contract import LabOptions, Running, ViewRequest, World
from app.worlds.port import LabPort

COMMAND_TOPIC = "/cartesian_velocity_controller/command"


def make_lab(options: LabOptions) -> Lab:
    return Lab(options.config, realtime=options.realtime, controller=options.controller)


def make_view(request: ViewRequest) -> Running:
    from app.lab.view import LabView

    return LabView(
        request.lab,
        request.actions,
        request.services,
        request.host,
        request.port,
        light=request.light,
        controls=request.controls,
    )


def warm_up(lab: LabPort[Snapshot]) -> None:
    """franka_states' robot model loaded now, not on the event loop when a node first subscribes."""
    franka_state(lab.snapshot())


LIFTING = World(
    name="lifting",
    lab=make_lab,
    topics=TOPICS,
    services=SERVICES,
    command_topic=COMMAND_TOPIC,
    command=commands.external_twist,
    view=make_view,
    actions=ACTIONS,
    exercises=EXERCISES,
    node_effects=NODE_EFFECTS,
    min_period_s=MIN_PERIOD_S,
    latched=frozenset(LATCHED),
    routes=(teleop.router, robot_routes.router, camera_api.router),
    warm_up=warm_up,
    grader="hri-lab grade",
)
