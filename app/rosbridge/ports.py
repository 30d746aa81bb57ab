"""What the parts of rosbridge see of each other, as Protocols: a capability, rosapi and the service
table are handed a session (SessionLike: one client's connection, app/rosbridge/session.py) and
through it the bridge (BridgeLike: what every session shares, app/rosbridge/bridge.py).
They import neither class, so neither imports them back."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Hashable, Iterable
from typing import Any, Protocol, TypeVar

from sim.messages import Topic

from app.ros.actions import ActionServer
from app.ros.node_actions import NodeActions
from app.ros.node_services import NodeClient, NodeServices
from app.ros.services import Service
from app.rosbridge.protocol import Id
from app.tokens import Throttle
from app.worlds.contract import Command
from app.worlds.port import LabPort

C = TypeVar("C")


class StreamLike(Protocol):
    """A topic as one client receives it (app/rosbridge/internal/streams.py)."""

    topic: str

    def offer(self, message: dict, header: dict | None = None) -> None: ...


class FramesLike(Protocol):
    """The frames programs publish on /tf and /tf_static (app/rosbridge/internal/node_frames.py)."""

    def offer(self, session: NodeClient, message: dict, static: bool) -> list[str]: ...

    def drop(self, session: NodeClient) -> None: ...

    def transforms(self, static: bool) -> list[dict]: ...

    def names(self) -> set[str]: ...

    def lab_frames(self) -> set[str]: ...

    @property
    def version(self) -> int: ...  # changes with every frame taken or dropped


class NodeTopicLike(Protocol):
    """A topic nodes publish: its type, the full text its first publisher carried, who is on it."""

    type: str
    lab: bool  # a topic of the lab's own node (tf2_web_republisher's action): kept while the lab runs
    definition: str
    publishers: set[SessionLike]
    subscriptions: set[StreamLike]


class SharedMessagesLike(Protocol):
    """What every client's stream of a topic shares (app/rosbridge/internal/shared.py)."""

    def trial(self, time_s: float) -> int: ...

    def built(self, topic: str, key: Hashable, make: Callable[[], dict]) -> dict: ...

    def frame(self, topic: str, message: dict, header: dict | None = None) -> str: ...

    def forget(self, topic: str) -> None: ...


class TFRepublisherLike(Protocol):
    """The lab's tf2_web_republisher action server (app/rosbridge/tf_republisher.py)."""

    @property
    def inputs(self) -> tuple[str, str]: ...  # its goal and cancel topics

    def take(self, session: SessionLike, topic: str, msg: dict) -> None: ...

    def drop(self, session: SessionLike) -> None: ...

    def start(self) -> None: ...

    def subscriptions(self) -> int: ...

    def held_by(self, session: SessionLike) -> int: ...

    def tree(self, snapshot: Any) -> tuple[Any, dict[str, tuple[Any, str]]]: ...


class ServiceEntryLike(Protocol):
    """One service a client may call (app/rosbridge/services.py)."""

    @property
    def name(self) -> str: ...

    @property
    def type(self) -> str: ...

    @property
    def writes(self) -> bool: ...  # with a token set, the caller must have presented it


class ServiceTableLike(Protocol):
    """Every service a client may call, by name (app/rosbridge/services.py)."""

    def get(self, name: str) -> ServiceEntryLike | None: ...

    def answers_itself(self, name: str) -> bool: ...

    def names(self) -> list[str]: ...

    def provider(self, name: str) -> str | None: ...

    async def call(
        self, caller: Caller, name: str, args: dict | list | None, header: dict[str, str] | None = None
    ) -> tuple[bool, object]: ...


class BridgeLike(Protocol):
    """What every session shares: the lab, its registries, the node topics, the sessions."""

    lab: LabPort[Any]  # any world's lab (app/worlds/port.py)
    nodes: NodeServices
    actions: ActionServer
    node_actions: NodeActions
    token: str | None
    graded: bool  # a graded trial's lab: a client without the token may act as a node, never as the lab's admin
    topics: dict[str, Topic]
    frames: FramesLike
    min_period_s: dict[str, float]
    command_topic: str
    command: Command  # what the lab runs with each Twist on command_topic (its world's)
    world_topics: list[Topic]  # the topics its world serves (rosapi's; `topics` is empty when replaying bags)
    latched: Iterable[str]
    node_topics: dict[str, NodeTopicLike]
    windows: dict[str, dict]
    sessions: list[SessionLike]
    auth_throttle: Throttle
    streams: int
    service_table: ServiceTableLike
    tf_republisher: TFRepublisherLike
    shared: SharedMessagesLike

    @property
    def services(self) -> Iterable[Service]: ...

    def fair_period(self) -> float: ...

    def next_name(self) -> str: ...

    def add_topic(self, topic: Topic, min_period_s: float = 0.0) -> None: ...

    def remove_topic(self, name: str) -> None: ...

    def topic_types(self) -> dict[str, str]: ...

    def room_for_topic(self, topic: str, op: str) -> None: ...

    def node_topic(self, topic: str, type_name: str) -> NodeTopicLike: ...

    def add_lab_node_topic(self, name: str, type_name: str) -> None: ...

    def lab_publishes(self, topic: str) -> bool: ...

    def leave(
        self, topic: str, publisher: SessionLike | None = None, subscription: StreamLike | None = None
    ) -> None: ...


class SessionLike(Protocol):
    """One client's connection, as a capability may use it."""

    bridge: BridgeLike
    client_name: str
    node_names: list[str]
    loop: asyncio.AbstractEventLoop | None
    authorized: bool
    address: str  # the client's address (its wrong tokens are slowed by it)
    closed: bool  # the client went (what it still sends is dropped)
    level: str
    in_flight: int  # its service calls and goals being served (capabilities/call_service.py)

    @property
    def name(self) -> str: ...

    async def send(self, message: dict) -> None: ...

    async def send_text(self, text: str) -> None: ...

    async def report(self, level: str, msg: str, id_: Id = None) -> None: ...

    def spawn(self, coroutine: Awaitable[object]) -> None: ...

    def capability(self, kind: type[C]) -> C: ...

    def details(self) -> dict[str, list[str]]: ...

    def endpoints(self, kind: str, name: str) -> list[dict]: ...


Closing = Callable[[], None]  # what goes with a client (e.g. a republished tf topic)


class Caller(Protocol):
    """Who calls a service of the table: a client's call_service capability (its session, the
    bridge, and what goes with the client: a /republish_tfs topic)."""

    session: SessionLike
    bridge: BridgeLike
    on_close: list[Closing]
