"""The connected rosbridge clients (app/rosbridge/session.py): at most MAX_CONNECTIONS at once, each
named /rosbridge_client_N until it names its node, and the wrong tokens of the auth op slowed per
client address (app/tokens.py's Throttle, the HTTP API's rule)."""

from __future__ import annotations

from app.rosbridge.ports import SessionLike
from app.rosbridge.protocol import MAX_CONNECTIONS
from app.tokens import Throttle


class SessionManager:
    def __init__(self) -> None:
        self._sessions: list[SessionLike] = []
        self.auth_throttle = Throttle()  # wrong tokens of the auth op, per client address (HTTP's rule)
        self._counter = 0

    def next_name(self) -> str:
        """A new client's name until it names its node (op node)."""
        self._counter += 1
        return f"/rosbridge_client_{self._counter}"

    def join(self, session: SessionLike) -> bool:
        """`session` is connected; False (and not joined) when MAX_CONNECTIONS are already."""
        if len(self._sessions) >= MAX_CONNECTIONS:
            return False
        self._sessions.append(session)
        return True

    def leave(self, session: SessionLike) -> None:
        if session in self._sessions:
            self._sessions.remove(session)

    def all(self) -> list[SessionLike]:
        """The connected clients, in the order they came (a copy)."""
        return list(self._sessions)
