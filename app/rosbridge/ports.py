"""What the parts of rosbridge see of each other, as Protocols: a capability, rosapi and the service
table are handed a session (SessionLike: one client's connection, app/rosbridge/session.py) and
through it the bridge (BridgeLike: what every session shares, app/rosbridge/bridge.py): the lab and
one manager per concern (app/rosbridge/managers/: topics, services, actions, tf, windows, sessions),
each Protocol here what a capability may call of it. They import no session, bridge or manager, so
none imports them back."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Hashable, Iterable
from typing import Any, Protocol, TypeVar

from sim.messages import Topic

from app.ros.actions import Action, GoalHandle
from app.ros.messages import RosMessage
from app.ros.node_services import NodeClient
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


class ServiceEntryLike(Protocol):
    """One service a client may call (app/rosbridge/services.py)."""

    @property
    def name(self) -> str: ...

    @property
    def type(self) -> str: ...

    @property
    def writes(self) -> bool: ...  # with a token set, the caller must have presented it


class TopicsLike(Protocol):
    """The topics (app/rosbridge/managers/topics.py): the lab's sampled ones, the nodes' relayed ones."""

    command_topic: str  # the topic the lab follows a node's Twists on
    command: Command  # what the lab runs with each Twist on command_topic (its world's)
    world_topics: list[Topic]  # the topics its world serves (rosapi's; the sampled ones are none when replaying bags)
    latched: Iterable[str]  # lab topics sent again only when their message changed
    shared: SharedMessagesLike

    def sampled(self, name: str) -> bool: ...

    def lab_topic(self, name: str) -> Topic | None: ...

    def sampled_names(self) -> list[str]: ...

    def min_period(self, name: str) -> float: ...

    def add_topic(self, topic: Topic, min_period_s: float = 0.0) -> None: ...

    def replace(self, topic: Topic) -> None: ...

    def remove_topic(self, name: str) -> None: ...

    def types(self) -> dict[str, str]: ...

    def lab_publishes(self, topic: str) -> bool: ...

    def definitions(self) -> dict[str, str]: ...

    def add_lab_node_topic(self, name: str, type_name: str) -> None: ...

    def find(self, topic: str) -> NodeTopicLike | None: ...

    def room_for_topic(self, topic: str, op: str) -> None: ...

    def advertise(self, topic: str, type_name: str, publisher: SessionLike, definition: str | None = None) -> None: ...

    def publishes(self, topic: str, session: SessionLike) -> bool: ...

    def publishers(self, topic: str) -> list[SessionLike]: ...

    def subscribe(self, topic: str, type_name: str, subscription: StreamLike) -> None: ...

    def subscribed(self, topic: str) -> bool: ...

    def deliver(self, topic: str, message: dict, header: dict | None = None) -> None: ...

    def unadvertise(self, topic: str, publisher: SessionLike) -> None: ...

    def unsubscribe(self, topic: str, subscription: StreamLike) -> None: ...

    def stream_opened(self) -> None: ...

    def stream_closed(self) -> None: ...

    def fair_period(self) -> float: ...


class ServicesLike(Protocol):
    """The services (app/rosbridge/managers/services.py): the one table a client calls, the ones
    nodes provide."""

    def get(self, name: str) -> ServiceEntryLike | None: ...

    def answers_itself(self, name: str) -> bool: ...

    def names(self) -> list[str]: ...

    def provider(self, name: str) -> str | None: ...

    async def call(
        self, caller: Caller, name: str, args: dict | list | None, header: dict[str, str] | None = None
    ) -> tuple[bool, object]: ...

    def registry(self) -> Iterable[Service]: ...

    def offered(self, name: str) -> bool: ...

    def lab_provides(self, name: str) -> bool: ...

    def room_for(self, name: str, op: str) -> None: ...

    def replaces_lab(self, name: str) -> bool: ...

    def advertise(
        self,
        name: str,
        type_name: str,
        session: NodeClient,
        text: str | None = None,
        models: tuple[type[RosMessage], type[RosMessage]] | None = None,
    ) -> str | None: ...

    def unadvertise(self, name: str, session: NodeClient) -> bool: ...

    def drop(self, session: NodeClient) -> None: ...

    def answer(self, session: NodeClient, call_id: object, ok: bool, values: Any) -> bool: ...


class ActionsLike(Protocol):
    """The actions (app/rosbridge/managers/actions.py): the lab's ActionServer, the nodes' actions."""

    def get(self, name: str) -> Action | None: ...

    def names(self) -> list[str]: ...

    def server_node(self, name: str) -> str | None: ...

    def send_goal(self, action: Action, goal: RosMessage) -> GoalHandle: ...

    def cancel(self, handle: GoalHandle) -> None: ...

    def advertise(self, name: str, type_name: str, session: NodeClient) -> None: ...

    def unadvertise(self, name: str, session: NodeClient) -> bool: ...

    def feedback(self, session: NodeClient, goal_id: object, name: str, values: Any) -> None: ...

    def result(self, session: NodeClient, goal_id: object, name: str, values: Any, status: int, ok: bool) -> None: ...

    def drop(self, session: NodeClient) -> None: ...


class TFLike(Protocol):
    """tf (app/rosbridge/managers/tf.py): the programs' frames and the lab's tf2_web_republisher."""

    def offer(self, session: SessionLike, message: dict, static: bool) -> list[str]: ...

    def drop(self, session: SessionLike) -> None: ...

    @property
    def inputs(self) -> tuple[str, str]: ...  # the action's goal and cancel topics

    def take(self, session: SessionLike, topic: str, message: dict) -> None: ...

    def start(self) -> None: ...

    def republish(self, session: SessionLike, args: dict) -> tuple[str, Closing]: ...


class WindowsLike(Protocol):
    """The programs' cv2.imshow windows (app/rosbridge/managers/windows.py)."""

    def show(self, topic: str, image: dict) -> None: ...

    def get(self, topic: str) -> dict | None: ...

    def shown(self) -> dict[str, dict]: ...


class SessionsLike(Protocol):
    """The connected clients (app/rosbridge/managers/sessions.py)."""

    auth_throttle: Throttle

    def next_name(self) -> str: ...

    def join(self, session: SessionLike) -> bool: ...

    def leave(self, session: SessionLike) -> None: ...

    def all(self) -> list[SessionLike]: ...


class BridgeLike(Protocol):
    """What every session shares: the lab, its access rule, and one manager per concern."""

    lab: LabPort[Any]  # any world's lab (app/worlds/port.py)
    token: str | None
    graded: bool  # a graded trial's lab: a client without the token may act as a node, never as the lab's admin

    @property
    def topics(self) -> TopicsLike: ...

    @property
    def services(self) -> ServicesLike: ...

    @property
    def actions(self) -> ActionsLike: ...

    @property
    def tf(self) -> TFLike: ...

    @property
    def windows(self) -> WindowsLike: ...

    @property
    def sessions(self) -> SessionsLike: ...


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
