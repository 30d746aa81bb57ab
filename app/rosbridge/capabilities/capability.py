"""A capability (rosbridge_suite's): one op family's part of one client. Each client's session
makes one object of every capability (app/rosbridge/ops.py lists them); it holds what the client
has open in that family (its subscriptions, publishers, goals ...) and gives it back in `finish()`,
which the session calls when the client goes. An op is declared by its module as Op(the
capability's class, its handler method, whether it changes the lab)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, TypeVar

from app.rosbridge.ports import BridgeLike, Id, SessionLike


class Capability:
    """One op family of one client: its state, its ops (methods), its `finish()`."""

    # what rosapi's node_details shows of this family for the client (subscribing, publishing, services)
    DETAILS: ClassVar[str | None] = None

    def __init__(self, session: SessionLike) -> None:
        self.session: SessionLike = session
        self.bridge: BridgeLike = session.bridge

    def finish(self) -> None:
        """The client is gone: what it holds of this family goes (nothing, unless overridden)."""

    def names(self) -> list[str]:
        """The topics or services this client has open in this family (rosapi's node_details)."""
        return []


C = TypeVar("C", bound=Capability)


@dataclass(frozen=True)
class Op(Generic[C]):
    """One op: handler(the client's capability object, the parsed frame, its id)."""

    capability: type[C]
    handler: Callable[[C, dict, Id], Awaitable[None]]
    mutating: bool = False  # with a token set, the client must have presented it


Ops = dict[str, Op[Any]]
