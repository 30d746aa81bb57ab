"""The connected clients (app/rosbridge/managers/sessions.py): named in turn until they name their
node, at most MAX_CONNECTIONS at once (one more is refused, not joined), and one that left makes room."""

import pytest

from app.rosbridge.managers.sessions import SessionManager
from app.rosbridge.session import Session
from app.tokens import Throttle
from tests.app.rosbridge.clients import Socket, parts


def test_clients_are_named_in_turn():
    sessions = SessionManager()
    assert [sessions.next_name() for _ in range(3)] == [
        "/rosbridge_client_1",
        "/rosbridge_client_2",
        "/rosbridge_client_3",
    ]
    assert isinstance(sessions.auth_throttle, Throttle)


def test_at_most_max_connections_join_and_one_that_left_makes_room(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr("app.rosbridge.managers.sessions.MAX_CONNECTIONS", 3)
    bridge = parts(replay=True).bridge
    clients = [Session(bridge, Socket()) for _ in range(4)]  # type: ignore[arg-type]  # a WebSocket's two members
    sessions = bridge.sessions
    assert [sessions.join(client) for client in clients] == [True, True, True, False]
    assert sessions.all() == clients[:3]
    sessions.all().clear()  # a copy: the clients stay connected
    sessions.leave(clients[1])
    sessions.leave(clients[1])  # twice: gone once
    assert sessions.all() == [clients[0], clients[2]]
    assert sessions.join(clients[3])
    assert sessions.all() == [clients[0], clients[2], clients[3]]
