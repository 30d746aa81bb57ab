"""/republish_tfs (tf2_web_republisher/RepublishTFs), the service roslibpy's and roslibjs'
TFClient call: the transforms of `source_frames` in `target_frame`, on a topic of their own
(tf2_web_republisher/TFArray) at `rate` Hz, which the service names in `topic_name`. The
frames are the lab's (app/lab/tf.py) and the programs' (app/rosbridge/internal/node_frames.py); the
topic goes when the client that asked for it does.
Deviation from tf2_web_republisher: every period sends all the transforms (it sends those that
moved beyond `trans_thres`/`angular_thres`); the first message is the same."""

from __future__ import annotations

import itertools
import math
from typing import Any

from sim.messages import Topic

from app.lab import tf
from app.ros.services import ServiceFailure

SERVICE = "/republish_tfs"
TYPE = "tf2_web_republisher/RepublishTFs"
ARRAY_TYPE = "tf2_web_republisher/TFArray"
MAX_RATE_HZ = 100.0
MAX_TOPICS = 64  # republisher topics at once (over all clients)
_NUMBERS = itertools.count(1)


def _frame(name: Any, field: str, known: set[str]) -> str:
    if not isinstance(name, str) or not name.strip("/"):
        raise ServiceFailure(f"republish_tfs: '{field}' must be a frame name like panda_link8")
    name = name.strip().strip("/")
    if name not in known:
        raise ServiceFailure(f"republish_tfs: frame '{name[:80]}' does not exist (frames: {', '.join(sorted(known))})")
    return name


def republish(session: Any, args: dict) -> dict:
    """Answer the service for `session`: a new topic of the transforms, named in the response."""
    sources = args.get("source_frames", [])
    if not isinstance(sources, list) or len(sources) > 100:
        raise ServiceFailure("republish_tfs: 'source_frames' must be a list of frame names (at most 100)")
    bridge = session.bridge
    known = bridge.frames.lab_frames() | bridge.frames.names()  # the lab's and the programs' (node_frames.py)
    sources = [_frame(name, "source_frames", known) for name in sources]
    target = _frame(args.get("target_frame", tf.WORLD), "target_frame", known)
    rate = args.get("rate", 10.0)
    if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not math.isfinite(rate) or rate <= 0:
        raise ServiceFailure("republish_tfs: 'rate' must be a positive number (Hz)")
    if len([n for n in bridge.topics if n.startswith("/tf_repub_")]) >= MAX_TOPICS:
        raise ServiceFailure(f"republish_tfs: {MAX_TOPICS} republished topics exist already")

    def build(snapshot) -> dict:
        poses = bridge.frames.poses(tf.frames_in_world(snapshot))  # a frame whose program went: left out
        return {
            "transforms": [
                tf.transform_stamped(snapshot, target, source, poses[target], poses[source])
                for source in sources
                if source in poses and target in poses
            ]
        }

    name = f"/tf_repub_{next(_NUMBERS)}"
    bridge.add_topic(Topic(name, ARRAY_TYPE, build), min_period_s=1.0 / min(float(rate), MAX_RATE_HZ))
    session.on_close.append(lambda: bridge.remove_topic(name))
    return {"topic_name": name}
