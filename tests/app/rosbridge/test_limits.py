"""rosbridge under hostile clients (issue 44, item 4): what one client, and all of them together, may
hold open (app/rosbridge/protocol.py's caps), a definition's field count (interfaces/parser.py),
the models of a carried definition built off the event loop and given back when the client goes,
the connections, wrong tokens slowed as HTTP's, /republish_tfs capped per client, a transform that
closes a loop in /tf refused, the tf tree built once per period, the served world's own frames. Each
refusal is a status message naming the cap; the session and the lab go on."""

import asyncio
import gc
import weakref
from types import SimpleNamespace

import pytest

from sim.messages import Topic

from app.mobile.lab import MobileLab
from app.mobile.world import MOBILE
from app.rosbridge import protocol
from app.rosbridge.capabilities import connection
from app.rosbridge.internal import message_conversion
from app.rosbridge.internal.node_frames import NodeFrames
from app.rosbridge.session import Session
from app.serving.compose import build
from interfaces.parser import MAX_DEFINITION_FIELDS
from tests.app.rosbridge.clients import Socket, connect, op, parts, run, sent, until

TOKEN = "s3cret-0123456789abcdef"


def errors(answers: list[dict]) -> list[str]:
    return [m["msg"] for m in answers if m.get("op") == "status" and m.get("level") == "error"]


def test_a_client_advertises_at_most_its_cap_of_topics_and_all_together_at_most_theirs():
    async def check() -> None:
        lab = parts(replay=True)
        first = await connect(lab)
        for i in range(protocol.MAX_CLIENT_TOPICS):
            assert await op(first, op="advertise", topic=f"/a/{i}", type="std_msgs/String") == [], i
        refused = errors(await op(first, op="advertise", topic="/a/one_more", type="std_msgs/String"))
        assert refused == [f"advertise: at most {protocol.MAX_CLIENT_TOPICS} topics per client (unadvertise one first)"]
        others = [await connect(lab) for _ in range(protocol.MAX_TOPICS // protocol.MAX_CLIENT_TOPICS)]
        said: list[str] = []
        for n, other in enumerate(others):
            for i in range(protocol.MAX_CLIENT_TOPICS):
                said += errors(await op(other, op="advertise", topic=f"/b{n}/{i}", type="std_msgs/String"))
        assert (
            len(lab.bridge.topics.node_topic_names()) - 5 == protocol.MAX_TOPICS
        )  # the 5 of the tf2_web_republisher action
        assert said and set(said) == {
            f"advertise: at most {protocol.MAX_TOPICS} topics exist already (the lab's limit, all clients together)"
        }
        refused = errors(await op(others[0], op="subscribe", topic="/c/new", type="std_msgs/String"))
        assert refused[0].startswith("subscribe: at most")
        await first.close()  # its topics go: room again
        assert await op(others[-1], op="advertise", topic="/b/after", type="std_msgs/String") == []

    run(check())


SRV = "int64 a\n---\nint64 b\n"


def test_a_client_provides_at_most_its_cap_of_services_and_all_together_at_most_theirs():
    async def check() -> None:
        lab = parts(replay=True)
        clients = [await connect(lab) for _ in range(protocol.MAX_SERVICES // protocol.MAX_CLIENT_SERVICES + 1)]
        for i in range(protocol.MAX_CLIENT_SERVICES):
            assert errors(await op(clients[0], op="advertise_service", service=f"/s0/{i}", type="p/S")) == []
        refused = errors(await op(clients[0], op="advertise_service", service="/s0/more", type="p/S"))
        assert refused == [
            f"advertise_service: at most {protocol.MAX_CLIENT_SERVICES} services per client (unadvertise one first)"
        ]
        said: list[str] = []
        for n, client in enumerate(clients[1:], 1):
            for i in range(protocol.MAX_CLIENT_SERVICES):
                said += errors(
                    await op(client, op="advertise_service", service=f"/s{n}/{i}", type="p/S", definition=SRV)
                )
        assert len(lab.bridge.services.nodes.providers) == protocol.MAX_SERVICES
        assert set(said) == {
            f"advertise_service: at most {protocol.MAX_SERVICES} services are provided by nodes already "
            "(the lab's limit, all clients together)"
        }

    run(check())


def fields_definition(n: int) -> str:
    return "\n".join(f"int64 f{i}" for i in range(n)) + "\n---\nbool ok\n"


def test_a_definition_over_the_field_cap_is_refused_naming_it():
    async def check() -> None:
        session = await connect(parts(replay=True))
        refused = errors(
            await op(
                session,
                op="advertise_service",
                service="/wide",
                type="p/Wide",
                definition=fields_definition(MAX_DEFINITION_FIELDS + 1),
            )
        )
        assert refused == [
            f"advertise_service: the definition of p/Wide cannot be read: it has {MAX_DEFINITION_FIELDS + 2} "
            f"fields, over the cap of {MAX_DEFINITION_FIELDS} (its types' fields counted once each)"
        ]
        assert errors(await op(session, op="advertise", topic="/still_here", type="std_msgs/String")) == []

    run(check())


def test_a_definitions_models_are_built_off_the_event_loop_and_go_with_the_client():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        ticks = [0]

        async def ticker() -> None:
            while True:
                ticks[0] += 1
                await asyncio.sleep(0)

        task = asyncio.ensure_future(ticker())
        await asyncio.sleep(0)
        before = ticks[0]
        definition = fields_definition(MAX_DEFINITION_FIELDS - 1)
        assert (
            errors(await op(session, op="advertise_service", service="/at_cap", type="p/AtCap", definition=definition))
            == []
        )
        assert ticks[0] > before  # the loop ran other tasks while the models were built
        task.cancel()
        model = weakref.ref(lab.bridge.services.service("/at_cap").request)
        await session.close()
        assert lab.bridge.services.get("/at_cap") is None
        # nothing keeps the client's models once it left (the loop lets go of the finished build's future)
        await until(lambda: gc.collect() >= 0 and model() is None, "the models collected")

    run(check())


class RefusedSocket(Socket):
    """A socket that connects and, if let in, disconnects at once; what it was closed with."""

    def __init__(self) -> None:
        super().__init__()
        self.closed_with: int | None = None

    async def accept(self) -> None:
        pass

    async def receive(self) -> dict:
        return {"type": "websocket.disconnect"}

    async def close(self, code: int = 1000, reason: str = "") -> None:
        self.closed_with = code


def test_connections_beyond_the_cap_are_closed_with_the_reason():
    async def check() -> None:
        lab = parts(replay=True)
        for _ in range(protocol.MAX_CONNECTIONS):
            await connect(lab)
        socket = RefusedSocket()
        await Session(lab.bridge, socket).run()  # type: ignore[arg-type]
        assert socket.closed_with == 1013
        assert socket.sent[0]["msg"] == (
            f"this lab serves at most {protocol.MAX_CONNECTIONS} rosbridge connections at once: try again later"
        )
        assert len(lab.bridge.sessions.all()) == protocol.MAX_CONNECTIONS
        await lab.bridge.sessions.all()[0].close()
        let_in = RefusedSocket()
        await Session(lab.bridge, let_in).run()  # type: ignore[arg-type]
        assert let_in.closed_with is None and let_in.sent == []

    run(check())


def test_wrong_tokens_are_answered_after_the_https_doubling_delay(monkeypatch):
    waited: list[float] = []

    async def sleep(seconds: float) -> None:
        waited.append(seconds)

    monkeypatch.setattr(connection.asyncio, "sleep", sleep)

    async def check() -> None:
        lab = parts(token=TOKEN, replay=True)
        session = await connect(lab)
        for _ in range(7):
            assert errors(await op(session, op="auth", mac="wrong")) == ["auth: wrong token"]
        assert waited == [0.1, 0.2, 0.4, 0.8, 1.6, 2.0, 2.0]  # app/tokens.py's Throttle, as HTTP's
        assert await op(session, op="auth", mac=TOKEN) == []
        assert session.authorized

    run(check())


def test_a_client_holds_at_most_its_cap_of_republished_tf_topics():
    async def check() -> None:
        lab = parts(token=TOKEN)
        greedy, other = await connect(lab), await connect(lab)
        args = {"source_frames": ["panda_link8"], "target_frame": "world"}
        for i in range(protocol.MAX_CLIENT_TF_REPUBLISHED):
            (answer,) = await op(greedy, op="call_service", id=i, service="/republish_tfs", args=args)
            assert answer["result"] is True, answer
        answers = await op(greedy, op="call_service", id="more", service="/republish_tfs", args=args)
        (refused,) = [m for m in answers if m["op"] == "service_response"]
        assert refused["result"] is False
        assert refused["values"] == (
            f"republish_tfs: this client holds {protocol.MAX_CLIENT_TF_REPUBLISHED} republished topics and goals "
            "already (the limit per client)"
        )
        (answer,) = await op(other, op="call_service", id=1, service="/republish_tfs", args=args)
        assert answer["result"] is True

    run(check())


def stamped(parent: str, child: str) -> dict:
    return {
        "header": {"frame_id": parent},
        "child_frame_id": child,
        "transform": {"translation": {"x": 1.0, "y": 0.0, "z": 0.0}, "rotation": {"w": 1.0}},
    }


def test_a_transform_that_closes_a_loop_is_refused_naming_it():
    frames, ada = NodeFrames(), SimpleNamespace(name="/ada")
    chain = [stamped("world", "f0")] + [stamped(f"f{i}", f"f{i + 1}") for i in range(999)]
    assert frames.offer(ada, {"transforms": chain}, static=False) == []
    assert frames.offer(ada, {"transforms": [stamped("f999", "f0")]}, static=False) == [
        "frame f0: its parent f999 hangs below it: the transform would close a loop in the tree"
    ]
    assert frames.offer(ada, {"transforms": [stamped("f998", "f999")]}, static=False) == []  # the same again


def test_the_tf_tree_is_built_once_a_period_for_every_goal_and_republished_topic():
    async def check() -> None:
        lab = parts()
        bridge = lab.bridge
        built = [0]
        tf_topic = bridge.topics.lab_topic("/tf")

        def counted(snapshot) -> dict:
            built[0] += 1
            return tf_topic.build(snapshot)

        bridge.topics.replace(Topic("/tf", tf_topic.type, counted))
        client = await connect(lab)
        await op(
            client,
            op="advertise",
            topic="/tf2_web_republisher/goal",
            type="tf2_web_republisher/TFSubscriptionActionGoal",
        )
        await op(client, op="subscribe", topic="/tf2_web_republisher/feedback")
        for n in range(4):
            body = {"source_frames": ["plate"], "target_frame": "world", "rate": 100.0}
            msg = {"goal_id": {"id": f"g{n}"}, "goal": body}
            await op(client, op="publish", topic="/tf2_web_republisher/goal", msg=msg)
        await until(lambda: len(sent(client, "publish")) >= 20, "20 feedback messages")
        assert built[0] == 1  # the lab stands still (never started): one snapshot, one tree

    run(check())


@pytest.mark.parametrize("frame", ["base_footprint", "odom", "base_scan", "wheel_left_link"])
def test_programs_cannot_publish_the_mobile_worlds_own_frames(frame):
    async def check() -> None:
        lab = build(MOBILE, MobileLab())
        session = await connect(lab)
        await op(session, op="advertise", topic="/tf", type="tf2_msgs/TFMessage")
        refused = errors(await op(session, op="publish", topic="/tf", msg={"transforms": [stamped("map", frame)]}))
        assert refused == [
            f"publish /tf: refused frame {frame} is the lab's: a program cannot move it (publish frames of your own, below it)"
        ]

    run(check())


def test_the_converter_of_a_definition_a_client_brought_goes_with_it():
    async def check() -> None:
        lab = parts(replay=True)
        talker, listener = await connect(lab), await connect(lab)
        definition = "string name\nint32 age\n"
        await op(listener, op="subscribe", topic="/student", type="student_pkg/Info")
        await op(talker, op="advertise", topic="/student", type="student_pkg/Info", definition=definition)
        assert errors(await op(talker, op="publish", topic="/student", msg={"name": "ada"})) == []
        made = weakref.ref(message_conversion.converter("student_pkg/Info", definition))
        await talker.close()
        await listener.close()
        await until(lambda: gc.collect() >= 0 and made() is None, "the client's converter let go")

    run(check())


def test_a_client_that_goes_while_its_models_are_built_leaves_no_service():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        frame = {"op": "advertise_service", "service": "/late", "type": "p/Late", "definition": fields_definition(400)}
        advertising = asyncio.ensure_future(op(session, **frame))
        await asyncio.sleep(0)  # the op is waiting for its models' thread
        await session.close()
        await advertising
        assert lab.bridge.services.get("/late") is None
        assert lab.bridge.services.nodes.providers == {}

    run(check())
