"""One rosbridge connection: the ops of rosbridge v2 on the lab's registries.

- topics: subscribe (throttle_rate ms, queue_length; one stream per topic and client, at the
  lowest throttle and longest queue of its subscriptions, as rosbridge does), unsubscribe;
  advertise / publish / unadvertise. The lab's topics are sampled from its snapshot (newest
  first; what a slow client cannot take is dropped, the simulation never waits). A node's
  Twist on /cartesian_velocity_controller/command drives the robot (commands.external_twist);
  other topics that nodes advertise are relayed between nodes.
- services: call_service on the lab's registry (rosapi included), advertise_service /
  unadvertise_service / service_response for services a node provides (app/rosbridge/nodes.py).
- actions: send_action_goal (feedback when asked) / cancel_action_goal on the lab's ActionServer,
  answered with action_feedback and action_result (status as action_msgs/GoalStatus).
Every refusal is a `status` message naming the op and the field; the connection goes on, except
for a frame beyond MAX_FRAME (closed with 1009).
"""
from __future__ import annotations

import asyncio
import json
import math
from collections import deque
from typing import Any

from fastapi import WebSocket
from pydantic import ValidationError

from app.api.access import presented_token, token_matches
from app.lab import commands as cmd
from app.ros.actions import TERMINAL, GoalStatus
from app.ros.services import ServiceFailure
from app.rosbridge import rosapi
from app.rosbridge.bridge import COMMAND_TOPIC, Bridge, NodeTopic
from app.rosbridge.nodes import normalise_type
from app.rosbridge.protocol import LEVELS, MAX_FRAME, BadFrame, field, name_field, parse, status

MAX_CALLS_IN_FLIGHT = 64  # per client: service calls and goals being served at once
MAX_QUEUE = 1000  # queue_length cap
MAX_COMMANDS_IN_FLIGHT = 8  # node commands sent to the simulation and not yet applied
GOAL_STATUS = {GoalStatus.SUCCEEDED: 4, GoalStatus.PREEMPTED: 5, GoalStatus.ABORTED: 6, GoalStatus.REJECTED: 6}
MUTATING = {"advertise", "publish", "advertise_service", "unadvertise_service", "service_response",
            "send_action_goal", "cancel_action_goal"}


class Stream:
    """A topic as one client receives it: newest messages in a bounded queue, sent in order.

    A lab topic is paced where it is sampled (Session._sample, simulation time). A node topic is
    paced here, on the sending side, as rosbridge's queue does: every message is queued (full: the
    oldest is dropped) and the sender waits out the throttle period (wall clock) before the next, so
    the newest message of a burst is always sent, at most one throttle period late."""

    def __init__(self, session: "Session", topic: str, paced: bool = False) -> None:
        self.session, self.topic, self.paced = session, topic, paced
        self.options: dict[Any, tuple[int, int]] = {}  # subscription id -> (throttle_rate ms, queue_length)
        self.queue: deque[dict] = deque(maxlen=1)
        self.ready = asyncio.Event()
        self.last_sent = -math.inf  # s, loop time of the last message sent (paced streams)
        self.tasks: list[asyncio.Task] = []

    @property
    def period(self) -> float:
        """s between messages: the lowest throttle_rate of the subscriptions (at most 1 kHz)."""
        return max(min(t for t, _ in self.options.values()) / 1000.0, 0.001)

    def configure(self) -> None:
        length = max(max(q for _, q in self.options.values()), 1)
        if length != self.queue.maxlen:
            self.queue = deque(self.queue, maxlen=length)

    def offer(self, message: dict) -> None:
        """Queue a message for the sender (full: the oldest is dropped); never refused."""
        self.queue.append(message)
        self.ready.set()

    async def deliver(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            await self.ready.wait()
            self.ready.clear()
            while self.queue:
                if self.paced:
                    wait = self.last_sent + self.period - loop.time()
                    if wait > 0:  # newer messages may come meanwhile: the queue is read after the wait
                        await asyncio.sleep(wait)
                        continue
                    self.last_sent = loop.time()
                await self.session.send({"op": "publish", "topic": self.topic, "msg": self.queue.popleft()})

    def stop(self) -> None:
        for task in self.tasks:
            task.cancel()


class Session:
    def __init__(self, bridge: Bridge, websocket: WebSocket) -> None:
        self.bridge, self.ws = bridge, websocket
        self.lab = bridge.lab
        self.name = bridge.next_name()
        self.loop: asyncio.AbstractEventLoop | None = None
        token = bridge.token
        self.authorized = token is None or token_matches(presented_token(websocket.scope["headers"]), token)
        self.level = "error"
        self.streams: dict[str, Stream] = {}
        self.publishing: set[str] = set()
        self.services: set[str] = set()
        self.goals: dict[Any, Any] = {}  # goal id -> GoalHandle
        self.tasks: set[asyncio.Task] = set()
        self.in_flight = 0
        self.closed = False
        self._send_lock = asyncio.Lock()
        self._command: list[float] | None = None  # newest Twist not yet handed to the simulation
        self._commanding = False
        self._commands_in_flight = 0

    # --- connection -------------------------------------------------------------------------
    async def run(self) -> None:
        await self.ws.accept()
        self.loop = asyncio.get_running_loop()
        self.bridge.sessions.append(self)
        try:
            while True:
                frame = await self.ws.receive()
                if frame["type"] == "websocket.disconnect":
                    break
                text = frame.get("text")
                if text is None:
                    data = frame.get("bytes") or b""
                    text = data.decode("utf-8", errors="replace")
                if len(text) > MAX_FRAME:
                    await self.report("error", f"frame of {len(text)} characters refused (limit {MAX_FRAME})")
                    await self.ws.close(code=1009, reason="frame too large")
                    break
                await self.handle(text)
        except Exception:  # noqa: BLE001 - a broken connection ends this session only
            pass
        finally:
            await self.close()

    async def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.bridge.sessions.remove(self)
        self.bridge.nodes.drop(self)
        for stream in self.streams.values():
            stream.stop()
            self.bridge.leave(stream.topic, subscription=stream)
        for topic in self.publishing:
            self.bridge.leave(topic, publisher=self)
        for handle in self.goals.values():  # the client is gone: its goals stop
            if handle.status not in TERMINAL:
                self.bridge.actions.cancel(handle)
        for task in list(self.tasks):
            task.cancel()

    async def send(self, message: dict) -> None:
        if self.closed:
            return
        text = json.dumps(message)
        async with self._send_lock:
            try:
                await self.ws.send_text(text)
            except Exception:  # noqa: BLE001 - the client went away; run() ends the session
                pass

    async def report(self, level: str, msg: str, id_: Any = None) -> None:
        """A status message, if the client's level shows it (rosbridge's default: errors)."""
        order = LEVELS.index
        if self.level != "none" and order(level) >= order(self.level):
            await self.send(status(level, msg, id_))

    def spawn(self, coroutine) -> None:
        task = asyncio.ensure_future(coroutine)
        self.tasks.add(task)
        task.add_done_callback(self.tasks.discard)

    def details(self) -> dict:
        return {"subscribing": list(self.streams), "publishing": list(self.publishing), "services": list(self.services)}

    # --- dispatch ---------------------------------------------------------------------------
    async def handle(self, text: str) -> None:
        id_ = None
        try:
            message = parse(text)
            id_ = message.get("id") if isinstance(message.get("id"), (str, int)) else None
            op = message["op"]
            handler = getattr(self, "op_" + op, None) if op.isidentifier() else None
            if handler is None:
                raise BadFrame(f"unknown op '{op[:40]}'")
            if op in MUTATING and not self.authorized:
                raise BadFrame(f"{op}: this lab needs a token for changes: connect with 'Authorization: Bearer "
                               f"<token>' or send {{\"op\": \"auth\", \"mac\": \"<token>\"}}")
            await handler(message, id_)
        except BadFrame as bad:
            await self.report("error", str(bad), id_)
        except Exception as exc:  # noqa: BLE001 - a bug here is reported, the connection goes on
            await self.report("error", f"internal error: {type(exc).__name__}: {exc}", id_)

    async def op_auth(self, message: dict, id_: Any) -> None:
        if self.bridge.token is None:
            return
        self.authorized = token_matches(field(message, "mac", str), self.bridge.token)
        if not self.authorized:
            raise BadFrame("auth: wrong token")

    async def op_set_level(self, message: dict, id_: Any) -> None:
        level = field(message, "level", str)
        if level in LEVELS:  # rosbridge drops a bad level silently
            self.level = level

    async def op_fragment(self, message: dict, id_: Any) -> None:
        raise BadFrame("fragment: fragmented messages are not supported by this lab; send the whole message")

    async def op_png(self, message: dict, id_: Any) -> None:
        raise BadFrame("png: PNG-compressed messages are not supported by this lab")

    # --- topics -----------------------------------------------------------------------------
    async def op_subscribe(self, message: dict, id_: Any) -> None:
        topic = name_field(message, "topic")
        type_name = field(message, "type", str, None)
        throttle = field(message, "throttle_rate", int, 0)
        queue_length = field(message, "queue_length", int, 0)
        if throttle < 0 or queue_length < 0:
            raise BadFrame("subscribe: 'throttle_rate' and 'queue_length' must be >= 0")
        compression = field(message, "compression", str, "none")
        if compression not in ("none", ""):
            raise BadFrame(f"subscribe: compression '{compression[:20]}' is not supported (only none)")
        known = self.bridge.topic_types().get(topic)
        if known is None and not type_name:
            raise BadFrame(f"subscribe: topic {topic} does not exist (give its 'type' to wait for a publisher)")
        if known is not None and type_name and normalise_type(type_name) != known:
            raise BadFrame(f"subscribe: topic {topic} is of type {known}, not {type_name}")
        stream = self.streams.get(topic)
        if stream is None:
            lab_topic = self.bridge.topics.get(topic)
            stream = self.streams[topic] = Stream(self, topic, paced=lab_topic is None)
            stream.options[id_] = (throttle, min(queue_length, MAX_QUEUE))
            stream.configure()
            stream.tasks.append(asyncio.ensure_future(stream.deliver()))
            if lab_topic is not None:
                stream.tasks.append(asyncio.ensure_future(self._sample(stream, lab_topic)))
            else:
                entry = self.bridge.node_topics.setdefault(topic, NodeTopic(normalise_type(type_name or known)))
                entry.subscriptions.add(stream)
        else:
            stream.options[id_] = (throttle, min(queue_length, MAX_QUEUE))
            stream.configure()

    async def _sample(self, stream: Stream, topic) -> None:
        """A lab topic from the snapshot: at most one message per throttle_rate of simulation time
        (rosbridge's minimum gap), paced by the wall clock; behind, it skips, it never queues up."""
        loop = asyncio.get_running_loop()
        due, last = loop.time(), None
        while True:
            snapshot = self.lab.snapshot()
            period = stream.period
            if last is None or snapshot.time - last >= period - 0.0005:
                last = snapshot.time
                stream.offer(topic.build(snapshot))
                due = max(due + period, loop.time())
            else:  # early (the wall clock ran ahead of the simulation): wait for the rest
                due = loop.time() + period - (snapshot.time - last)
            await asyncio.sleep(due - loop.time())

    async def op_unsubscribe(self, message: dict, id_: Any) -> None:
        topic = name_field(message, "topic")
        stream = self.streams.get(topic)
        if stream is None:
            await self.report("warning", f"unsubscribe: not subscribed to {topic}", id_)
            return
        if id_ is not None and id_ in stream.options and len(stream.options) > 1:
            del stream.options[id_]
            stream.configure()
            return
        stream.stop()
        del self.streams[topic]
        self.bridge.leave(topic, subscription=stream)

    async def op_advertise(self, message: dict, id_: Any) -> None:
        topic = name_field(message, "topic")
        type_name = normalise_type(field(message, "type", str))
        known = self.bridge.topic_types().get(topic)
        if topic in self.bridge.topics and topic != COMMAND_TOPIC:
            raise BadFrame(f"advertise: topic {topic} is published by the lab")
        if known is not None and known != type_name:
            raise BadFrame(f"advertise: topic {topic} is of type {known}, not {type_name}")
        if topic != COMMAND_TOPIC:
            entry = self.bridge.node_topics.setdefault(topic, NodeTopic(type_name))
            entry.publishers.add(self)
        self.publishing.add(topic)

    async def op_unadvertise(self, message: dict, id_: Any) -> None:
        topic = name_field(message, "topic")
        if topic not in self.publishing:
            await self.report("warning", f"unadvertise: {topic} is not advertised by this client", id_)
            return
        self.publishing.discard(topic)
        self.bridge.leave(topic, publisher=self)

    async def op_publish(self, message: dict, id_: Any) -> None:
        topic = name_field(message, "topic")
        msg = field(message, "msg", dict)
        if topic == COMMAND_TOPIC:
            self._command = twist_values(msg)
            if not self._commanding:
                self._commanding = True
                self.spawn(self._forward_commands())
            return
        if topic in self.bridge.topics:
            raise BadFrame(f"publish: topic {topic} is published by the lab")
        entry = self.bridge.node_topics.get(topic)
        if entry is None or self not in entry.publishers:
            raise BadFrame(f"publish: advertise {topic} first (op advertise with its type)")
        for stream in list(entry.subscriptions):
            stream.offer(msg)

    async def _forward_commands(self) -> None:
        """Node commands into the simulation, newest first: sent without waiting for the step that
        applies them, at most MAX_COMMANDS_IN_FLIGHT unanswered (beyond, a flood is coalesced)."""
        try:
            while self._command is not None:
                if self._commands_in_flight >= MAX_COMMANDS_IN_FLIGHT:
                    await asyncio.sleep(0.001)
                    continue
                twist, self._command = self._command, None
                self._commands_in_flight += 1
                future = self.lab.runtime.submit(cmd.external_twist, twist)
                future.add_done_callback(lambda f: self.loop.call_soon_threadsafe(self._command_done, f))
        finally:
            self._commanding = False

    def _command_done(self, future) -> None:
        self._commands_in_flight -= 1
        if future.exception() is not None:
            self.spawn(self.report("error", f"publish {COMMAND_TOPIC}: {future.exception()}"))

    # --- services ---------------------------------------------------------------------------
    async def op_advertise_service(self, message: dict, id_: Any) -> None:
        name = name_field(message, "service")
        type_name = field(message, "type", str)
        if name.startswith("/rosapi/"):
            raise BadFrame(f"advertise_service: {name} is the lab's")
        try:
            self.bridge.nodes.advertise(name, type_name, self)
        except ServiceFailure as failure:
            raise BadFrame(f"advertise_service: {failure}") from None
        self.services.add(name)
        await self.report("info", f"advertise_service: {name} [{type_name}] is provided by {self.name}", id_)

    async def op_unadvertise_service(self, message: dict, id_: Any) -> None:
        name = name_field(message, "service")
        if not self.bridge.nodes.unadvertise(name, self):
            await self.report("warning", f"unadvertise_service: {name} is not provided by this client", id_)
        self.services.discard(name)

    async def op_service_response(self, message: dict, id_: Any) -> None:
        ok = field(message, "result", bool, True)
        values = message.get("values")
        if not self.bridge.nodes.answer(self, message.get("id"), ok, values):
            await self.report("warning", f"service_response: no call with id {json.dumps(message.get('id'))[:80]} "
                                         f"waits for this client's answer", id_)

    async def op_call_service(self, message: dict, id_: Any) -> None:
        name = name_field(message, "service")
        args = message.get("args")
        if args is not None and not isinstance(args, (dict, list)):
            raise BadFrame("call_service: field 'args' must be an object (or a list of the request's fields in order)")
        if name in rosapi.WRITING or (name not in rosapi.READ_ONLY and not name.startswith("/rosapi/")):
            if not self.authorized:
                raise BadFrame(f"call_service {name}: this lab needs a token for changes (op auth, or the "
                               f"Authorization header)")
        if self.in_flight >= MAX_CALLS_IN_FLIGHT:
            raise BadFrame(f"call_service: {MAX_CALLS_IN_FLIGHT} calls of this client are already in flight")
        self.in_flight += 1
        self.spawn(self._call(name, args, id_))

    async def _call(self, name: str, args: Any, id_: Any) -> None:
        try:
            ok, values = await self._serve(name, args)
        finally:
            self.in_flight -= 1
        response = {"op": "service_response", "service": name, "values": values, "result": ok}
        if id_ is not None:
            response["id"] = id_
        await self.send(response)
        if not ok:
            await self.report("error", f"call_service {name}: {values}", id_)

    async def _serve(self, name: str, args: Any) -> tuple[bool, Any]:
        bridge = self.bridge
        try:
            if name.startswith("/rosapi/"):
                return True, await asyncio.to_thread(rosapi.call, bridge, self, name, args if isinstance(args, dict) else {})
            service = bridge.services.get(name)
            if service is None:
                return False, f"service {name} does not exist"
            if isinstance(args, list):  # positional: the request's fields in order
                args = dict(zip([f.alias or n for n, f in service.request.model_fields.items()], args))
            try:
                request = service.request.model_validate(args or {})
            except ValidationError as exc:
                return False, "; ".join(f"{'.'.join(str(x) for x in e['loc']) or 'request'}: {e['msg']}" for e in exc.errors())
            if bridge.nodes.goes_to_node(name):
                response = await bridge.nodes.call_async(name, request)
            else:
                response = await asyncio.to_thread(service.handler, self.lab, request)
            return True, response.model_dump(by_alias=True)
        except ServiceFailure as failure:
            return False, str(failure)
        except Exception as exc:  # noqa: BLE001 - a handler bug is a failed call
            return False, f"{type(exc).__name__}: {exc}"

    # --- actions ----------------------------------------------------------------------------
    async def op_send_action_goal(self, message: dict, id_: Any) -> None:
        name = name_field(message, "action")
        args = field(message, "args", (dict, list), {})
        feedback = field(message, "feedback", bool, False)
        action = self.bridge.actions.get(name)
        if action is None:
            await self._result(name, id_, 6, False, f"action {name} does not exist")
            raise BadFrame(f"send_action_goal: action {name} does not exist")
        if isinstance(args, list):
            args = dict(zip([f.alias or n for n, f in action.goal.model_fields.items()], args))
        try:
            goal = action.goal.model_validate(args)
        except ValidationError as exc:
            reason = "; ".join(f"{'.'.join(str(x) for x in e['loc']) or 'goal'}: {e['msg']}" for e in exc.errors())
            await self._result(name, id_, 6, False, reason)
            raise BadFrame(f"send_action_goal {name}: {reason}") from None
        if self.in_flight >= MAX_CALLS_IN_FLIGHT:
            raise BadFrame(f"send_action_goal: {MAX_CALLS_IN_FLIGHT} calls of this client are already in flight")
        handle = self.bridge.actions.send_goal(action, goal)
        self.goals[id_ if id_ is not None else handle.id] = handle
        self.in_flight += 1
        self.spawn(self._follow(name, id_, handle, feedback))

    async def _follow(self, name: str, id_: Any, handle, feedback: bool) -> None:
        """action_feedback as it comes (when asked), then action_result."""
        sent = 0
        try:
            while True:
                view = handle.view(sent)
                if feedback:
                    for values in view["feedback"]:
                        await self.send({"op": "action_feedback", "id": id_, "action": name, "values": values})
                sent = view["feedback_count"]
                if handle.status in TERMINAL:
                    break
                await asyncio.sleep(0.02)
        finally:
            self.in_flight -= 1
        view = handle.view(sent)
        status_ = GoalStatus(view["status"])
        values = view["result"] if view["result"] is not None else view["message"]
        await self._result(name, id_, GOAL_STATUS.get(status_, 0), status_ == GoalStatus.SUCCEEDED, values)

    async def _result(self, name: str, id_: Any, code: int, ok: bool, values: Any) -> None:
        await self.send({"op": "action_result", "id": id_, "action": name, "values": values, "status": code, "result": ok})

    async def op_cancel_action_goal(self, message: dict, id_: Any) -> None:
        handle = self.goals.get(id_)
        if handle is None:
            raise BadFrame(f"cancel_action_goal: no goal with id {json.dumps(id_)[:80]} from this client")
        self.bridge.actions.cancel(handle)


def twist_values(msg: dict) -> list[float]:
    """geometry_msgs/Twist -> [vx, vy, vz, wx, wy, wz]; missing fields are 0, anything else but
    finite numbers is refused (no NaN/inf reaches the simulation)."""
    values = []
    for part in ("linear", "angular"):
        vector = msg.get(part, {})
        if not isinstance(vector, dict):
            raise BadFrame(f"publish {COMMAND_TOPIC}: field 'msg.{part}' must be an object with x, y, z")
        for axis in "xyz":
            value = vector.get(axis, 0.0)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise BadFrame(f"publish {COMMAND_TOPIC}: field 'msg.{part}.{axis}' must be a finite number, "
                               f"got {json.dumps(value)[:40]}")
            values.append(float(value))
    extra = set(msg) - {"linear", "angular"}
    if extra:
        raise BadFrame(f"publish {COMMAND_TOPIC}: geometry_msgs/Twist has no field '{sorted(extra)[0]}'")
    return values
