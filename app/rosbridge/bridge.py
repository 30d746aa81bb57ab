"""The bridge's shared state: the lab, its access rule and one manager per concern
(app/rosbridge/managers/: topics, services, actions, tf, windows, sessions), built around the
lab's world (its topics, their rates, the command topic: app/worlds/contract.py) and its registries
(handed in by the composition root, app/serving/compose.py). Every session
(app/rosbridge/session.py) and its capabilities call the managers; it imports no session
(app/rosbridge/ports.py has the shapes both see)."""

from __future__ import annotations

import threading
from typing import Any

from app.ros.actions import ActionServer
from app.ros.node_actions import NodeActions
from app.ros.node_services import NodeServices
from app.rosbridge.managers.actions import ActionManager
from app.rosbridge.managers.services import ServiceManager
from app.rosbridge.managers.sessions import SessionManager
from app.rosbridge.managers.tf import TFManager
from app.rosbridge.managers.topics import TopicManager
from app.rosbridge.managers.windows import Windows
from app.worlds.contract import World
from app.worlds.port import LabPort


class Bridge:
    """What every session shares: the lab, its token, and its managers."""

    def __init__(
        self,
        world: World,
        lab: LabPort[Any],
        nodes: NodeServices,
        actions: ActionServer,
        node_actions: NodeActions,
        token: str | None = None,
        replay: bool = False,
    ) -> None:
        self.lab, self.token = lab, token
        # a graded trial's lab (app/grading/wall_trial.py): a client without the token is the graded program, a node
        # as on a robot (it publishes, advertises, provides and calls its nodes' services); the lab's own services
        # stay the token's (app/rosbridge/session.py, capabilities/call_service.py)
        self.graded = lab.graded
        self.windows = Windows()  # a program's cv2.imshow window (topic) -> its newest image
        self.topics = TopicManager(world, lab.graded, replay, self.windows)  # the lab's topics and the nodes'
        self.services = ServiceManager(nodes)  # every service a client may call, the ones nodes provide
        self.actions = ActionManager(actions, node_actions)  # the lab's ActionServer, the actions nodes provide
        self.tf = TFManager(lab, self.topics)  # the programs' frames on /tf, the tf2_web_republisher
        self.sessions = SessionManager()  # the connected clients
        if self.topics.sampled_names() and world.warm_up is not None:
            # what its topics need loaded now, not on the event loop when a node first subscribes
            threading.Thread(target=world.warm_up, args=(lab,), name="rosbridge-warm-up", daemon=True).start()
