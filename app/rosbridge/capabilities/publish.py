"""publish: a node's message to the other subscribers of its topic; a geometry_msgs/Twist on the
command topic drives the robot (commands.external_twist, through the lab's one door); a log line
on /rosout joins the lab's log (app/ros/rosout.py); a program's transforms on /tf and /tf_static
join the lab's tree (app/rosbridge/internal/node_frames.py); a goal or a cancel of the
tf2_web_republisher action goes to the lab's server of it (app/rosbridge/tf_republisher.py). A node
topic's message of a type the lab knows is made whole once (its defaults filled, a field it does not
have or a wrong value refused: app/rosbridge/internal/message_conversion.py), as rosbridge_suite makes
a ROS message of it, and that one message goes to every subscriber."""

from __future__ import annotations

import asyncio
import json
import math
from concurrent.futures import Future

from app.ros import rosout
from app.rosbridge.capabilities.advertise import Advertise
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.internal.message_conversion import FieldError, populate
from app.rosbridge.internal.node_frames import TF_TOPICS
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import BadFrame, field, name_field
from interfaces.image_windows import WINDOWS

MAX_COMMANDS_IN_FLIGHT = 8  # node commands sent to the simulation and not yet applied


class Publish(Capability):
    """What this client publishes goes where its topic takes it: its Twists to the simulation (its
    Commands), its log lines to /rosout, its transforms into the lab's tree (the reasons a frame was
    refused told once each), other topics to their subscribers."""

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.commands: Commands | None = None
        self.tf_refused: set[str] = set()  # each reason once, not at the broadcaster's rate

    async def publish(self, message: dict, id_: Id) -> None:
        topic = name_field(message, "topic")
        msg = field(message, "msg", dict)
        bridge, advertised = self.bridge, self.session.capability(Advertise)
        if topic == bridge.topics.command_topic and self._command(topic, msg, advertised.publishing):
            return
        if topic == rosout.TOPIC:
            if topic not in advertised.publishing:
                raise BadFrame(f"publish: advertise {topic} first (op advertise with type {rosout.TYPE})")
            try:
                line = rosout.from_message(msg, advertised.rosout_type, self.session.name)
            except rosout.BadLogMessage as bad:
                raise BadFrame(f"publish {topic}: {bad}") from None
            bridge.lab.rosout.publish(line)
            return
        if topic in TF_TOPICS:  # a program's frames join the lab's tree; the lab's own frames stay the lab's
            if topic not in advertised.publishing:
                raise BadFrame(f"publish: advertise {topic} first (op advertise with type tf2_msgs/TFMessage)")
            offered = bridge.tf.offer(self.session, msg, TF_TOPICS[topic])
            refused = [reason for reason in offered if reason not in self.tf_refused]
            if refused:
                self.tf_refused.update(refused)
                raise BadFrame(f"publish {topic}: refused " + "; ".join(refused))
            return
        if bridge.topics.sampled(topic):
            raise BadFrame(f"publish: topic {topic} is published by the lab")
        entry = bridge.topics.find(topic)
        if entry is None or not bridge.topics.publishes(topic, self.session):
            raise BadFrame(f"publish: advertise {topic} first (op advertise with its type)")
        try:  # made whole once, shared by every subscriber (and the lab's readers of it below)
            msg = populate(entry.type, entry.definition, msg)
        except FieldError as error:
            raise BadFrame(f"publish {topic}: {error.describe(entry.type)}") from None
        if topic in bridge.tf.inputs:  # a goal or a cancel for the lab's tf2_web_republisher
            bridge.tf.take(self.session, topic, msg)
        if topic.startswith(WINDOWS):  # a program's cv2.imshow: the dashboard shows its newest image
            bridge.windows.show(topic, msg)
        header = advertised.connection_header(topic)  # for the streams that asked (capabilities/subscribe.py)
        advertised.keep(topic, msg, header)  # a latched publisher's history (capabilities/advertise.py)
        bridge.topics.deliver(topic, msg, header)

    def _command(self, topic: str, msg: dict, publishing: set[str]) -> bool:
        """A Twist on the command topic, handed to the simulation; True when that is all (a topic
        the lab publishes itself, the lifting world's, or a Twist sent without advertising), False
        when the topic's subscribers get it too (the mobile world's /cmd_vel, the nodes' own)."""
        if self.commands is None:
            self.commands = Commands(self.session)
        self.commands.offer(twist_values(msg, topic))
        return self.bridge.topics.sampled(topic) or topic not in publishing

    def finish(self) -> None:
        self.bridge.tf.drop(self.session)  # its frames leave the lab's tree, its tf2_web_republisher goals end


class Commands:
    """A client's Twists into the simulation, newest first: sent without waiting for the step that
    applies them, at most MAX_COMMANDS_IN_FLIGHT unanswered (beyond, a flood is coalesced)."""

    def __init__(self, session: SessionLike) -> None:
        self.session = session
        self.newest: list[float] | None = None  # the newest Twist not yet handed to the simulation
        self.forwarding = False
        self.in_flight = 0

    def offer(self, twist: list[float]) -> None:
        self.newest = twist
        if not self.forwarding:
            self.forwarding = True
            self.session.spawn(self.forward())

    async def forward(self) -> None:
        bridge, loop = self.session.bridge, asyncio.get_running_loop()  # the session's loop
        try:
            while self.newest is not None:
                if self.in_flight >= MAX_COMMANDS_IN_FLIGHT:
                    await asyncio.sleep(0.001)
                    continue
                twist, self.newest = self.newest, None
                self.in_flight += 1
                future = bridge.lab.submit(bridge.topics.command, twist)
                future.add_done_callback(lambda f: loop.call_soon_threadsafe(self.done, f))
        finally:
            self.forwarding = False

    def done(self, future: Future[object]) -> None:
        self.in_flight -= 1
        if future.exception() is not None:
            topic = self.session.bridge.topics.command_topic
            self.session.spawn(self.session.report("error", f"publish {topic}: {future.exception()}"))


def twist_values(msg: dict, topic: str) -> list[float]:
    """geometry_msgs/Twist -> [vx, vy, vz, wx, wy, wz]; missing fields are 0, anything else but
    finite numbers is refused (no NaN/inf reaches the simulation)."""
    values = []
    for part in ("linear", "angular"):
        vector = msg.get(part, {})
        if not isinstance(vector, dict):
            raise BadFrame(f"publish {topic}: field 'msg.{part}' must be an object with x, y, z")
        for axis in "xyz":
            value = vector.get(axis, 0.0)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise BadFrame(
                    f"publish {topic}: field 'msg.{part}.{axis}' must be a finite number, got {json.dumps(value)[:40]}"
                )
            values.append(float(value))
    extra = set(msg) - {"linear", "angular"}
    if extra:
        raise BadFrame(f"publish {topic}: geometry_msgs/Twist has no field '{sorted(extra)[0]}'")
    return values


OPS: Ops = {"publish": Op(Publish, Publish.publish, mutating=True)}
