"""The composition root (app/serving/compose.py): the lab's parts are built once and handed down — the
API, rosbridge and the parameter server share one service registry and one ActionServer, and the
nodes' parameters are the parameter server's `remote` — for the lifting lab and the mobile world."""

import pytest
from fastapi.testclient import TestClient

from app.lab.lab import Lab
from app.lab.services import NODE_EFFECTS
from app.lab.world import LIFTING
from app.mobile.lab import MobileLab
from app.mobile.world import MOBILE
from app.ros.node_params import NodeParameters
from app.serving.compose import build, create_app
from tests.waiting import within


def test_the_parts_share_one_registry_one_action_server_and_the_nodes_parameters():
    parts = build(LIFTING, Lab(), token="s3cret-0123456789abcdef", replay=True)
    bridge = parts.bridge
    assert bridge.services.nodes is parts.nodes
    assert bridge.services.registry() is parts.nodes.registry
    assert bridge.actions.server is parts.actions
    assert bridge.actions.nodes.server is parts.actions
    assert isinstance(parts.lab.params.remote, NodeParameters)
    assert parts.lab.params.remote.services is parts.nodes
    assert parts.nodes.effects == NODE_EFFECTS
    assert parts.nodes.lab is parts.lab
    assert bridge.token == "s3cret-0123456789abcdef"
    assert bridge.topics.sampled_names() == []
    assert parts.world is LIFTING
    assert "/count" in parts.actions.actions


def test_the_mobile_world_has_its_own_declarations_and_no_lifting_effects():
    parts = build(MOBILE, MobileLab())
    assert parts.world is MOBILE
    assert parts.actions_declared == []
    assert not parts.nodes.effects
    assert parts.bridge.topics.command_topic == "/cmd_vel"
    assert [t.name for t in parts.topics_declared] == [t.name for t in parts.lab.topics]


def test_the_app_serves_the_parts_it_was_handed():
    app = create_app(LIFTING, Lab())
    assert app.state.bridge.lab is app.state.lab
    assert app.state.bridge.actions.server is app.state.actions
    assert app.state.view is None  # no view asked for
    client = TestClient(app)  # not entered: the lab is not started, its services that need no simulation answer
    with client.websocket_connect("/") as rosbridge:
        rosbridge.send_json({"op": "call_service", "id": 1, "service": "/add_two_ints", "args": {"a": 1, "b": 2}})
        assert within(rosbridge.receive_json, 30, "the answer")["values"] == {"sum": 3}
    assert client.get("/services/add_two_ints").json()["type"] == "hri_lab/AddTwoInts"
    with pytest.raises(ValueError, match="token"):
        create_app(LIFTING, Lab(), token="short")
