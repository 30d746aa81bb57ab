"""tf: the frames programs publish on /tf and /tf_static (app/rosbridge/internal/node_frames.py),
joined to the lab's own on those topics, and the lab's tf2_web_republisher (its /republish_tfs
service and its action: app/rosbridge/tf_republisher.py), which resolves frames in the tree they
make. Caps: the republisher's (MAX_SUBSCRIPTIONS, all clients together; MAX_CLIENT_TF_REPUBLISHED
per client) and the programs' frames (MAX_FRAMES)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sim.messages import Topic

from app.rosbridge.internal.node_frames import TF_TOPICS, NodeFrames
from app.rosbridge.ports import FramesLike, SessionLike, TopicsLike
from app.rosbridge.tf_republisher import TFSubscriptionServer


def _with_programs_frames(topic: Topic, frames: FramesLike, static: bool) -> Topic:
    """The lab's /tf or /tf_static with the programs' transforms of that kind after its own."""

    def build(snapshot: Any) -> dict:
        return {"transforms": [*topic.build(snapshot)["transforms"], *frames.transforms(static)]}

    return Topic(topic.name, topic.type, build)


def _frames_of(topics: list[Topic], snapshot: Any) -> set[str]:
    """Every frame the lab's own /tf and /tf_static name (parents and children)."""
    frames = set()
    for topic in topics:
        for t in topic.build(snapshot)["transforms"]:
            frames |= {t["header"]["frame_id"].strip("/"), t["child_frame_id"].strip("/")}
    return frames


class TFManager:
    def __init__(self, lab: Any, topics: TopicsLike) -> None:
        own_tf = [topic for topic in topics.world_topics if topic.name in TF_TOPICS]
        # the frames programs publish: /tf and /tf_static carry them with the lab's, whose own frames
        # (the served world's, a replaying lab's too) no program may publish
        self.frames: FramesLike = NodeFrames(lambda: _frames_of(own_tf, lab.snapshot())) if own_tf else NodeFrames()
        for name, static in TF_TOPICS.items():
            if (topic := topics.lab_topic(name)) is not None:
                topics.replace(_with_programs_frames(topic, self.frames, static))
        self.republisher = TFSubscriptionServer(lab, topics, self.frames)  # its action's topics are the lab's node's

    # --- a program's frames ---
    def offer(self, session: SessionLike, message: dict, static: bool) -> list[str]:
        """Take a TFMessage's transforms from `session`; the reasons of those refused."""
        return self.frames.offer(session, message, static)

    def drop(self, session: SessionLike) -> None:
        """`session`'s client is gone: its frames leave the tree, its tf2_web_republisher goals end."""
        self.frames.drop(session)
        self.republisher.drop(session)

    # --- the tf2_web_republisher ---
    @property
    def inputs(self) -> tuple[str, str]:
        """The action's goal and cancel topics, which the lab's node subscribes to."""
        return self.republisher.inputs

    def take(self, session: SessionLike, topic: str, message: dict) -> None:
        """A goal or a cancel `session` published (BadFrame naming the field for one refused)."""
        self.republisher.take(session, topic, message)

    def start(self) -> None:
        """The action's status array, from the first client on (on the server's event loop)."""
        self.republisher.start()

    def republish(self, session: SessionLike, args: dict) -> tuple[str, Callable[[], None]]:
        """/republish_tfs: a new topic's name and what removes it (ServiceFailure with the reason)."""
        return self.republisher.republish(session, args)
