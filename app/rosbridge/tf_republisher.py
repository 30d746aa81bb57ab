"""tf2_web_republisher as the lab's own node: the transforms of `source_frames` in `target_frame`
for a web client, the two ways upstream's node (RobotWebTools/tf2_web_republisher) offers them.

- **/republish_tfs** (tf2_web_republisher/RepublishTFs), which roslibpy's TFClient calls: a topic of
  its own (tf2_web_republisher/TFArray) at `rate` Hz, named in `topic_name`; it goes when the client
  that asked for it does. A frame that is in no tree is refused with its name (upstream waits for it).
  Deviation: every period carries every transform (a sampled lab topic, shared by its subscribers).
- **The tf2_web_republisher action** (ROS 1's actionlib over its topics: `/tf2_web_republisher/goal`,
  `cancel`, `status`, `feedback`, `result`; tf2_web_republisher/TFSubscriptionAction), which
  roslibjs' TFClient uses: every goal is accepted, and its transforms come as its feedback at `rate`
  Hz until it is cancelled (PREEMPTED, with a result) or its client goes. As upstream, a goal sends a
  frame when it moved more than `trans_thres` (m) or turned more than `angular_thres` (rad, tf's
  Quaternion::angle: half the rotation's angle) since it was last sent (or a threshold is 0, or it
  was never sent), and nothing when no frame did; a frame not (yet) in the tree is left out until it
  is. The status array goes out at actionlib's 5 Hz.

The frames are the whole tree the lab's /tf and /tf_static carry — the world's own and the
programs' (app/rosbridge/internal/node_frames.py) — so either world's frames serve, and a pair
resolves when both frames hang in one tree.
"""

from __future__ import annotations

import asyncio
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin

from sim.messages import Topic

from app.ros import tf_messages as tf
from app.ros.services import ServiceFailure
from app.rosbridge.internal.node_frames import TF_TOPICS, transform_pose
from app.rosbridge.ports import FramesLike, TopicsLike
from app.rosbridge.protocol import MAX_CLIENT_TF_REPUBLISHED, BadFrame

SERVICE = "/republish_tfs"
TYPE = "tf2_web_republisher/RepublishTFs"
ARRAY_TYPE = "tf2_web_republisher/TFArray"
ACTION = "/tf2_web_republisher"  # upstream's node name, which its action server takes
ACTION_TYPE = "tf2_web_republisher/TFSubscriptionAction"
MAX_RATE_HZ = 100.0
MAX_SUBSCRIPTIONS = 64  # republished topics and goals at once (over all clients; one client's: protocol.py)
MAX_SOURCES = 100  # source frames of one request or goal
STATUS_PERIOD_S = 0.2  # actionlib's status_frequency (5 Hz)
ENDED_KEPT_S = 5.0  # actionlib's status_list_timeout: an ended goal stays in the status array so long
ACTIVE, PREEMPTED, REJECTED = 1, 2, 5  # actionlib_msgs/GoalStatus
_NUMBERS = itertools.count(1)


# --- the tree -------------------------------------------------------------------------------------
class FramePose(NamedTuple):
    """A frame's pose in another: its 4x4, and its rotation as tf2 composes it (x, y, z, w): by
    quaternion products along the chain (tf2's BufferCore::lookupTransform), so a frame's pose in its
    parent comes back with the quaternion its broadcaster sent, sign included (one read back from the
    matrix, as Eigen reads it, is its negative for a turn beyond 90 degrees about z)."""

    matrix: np.ndarray
    rotation_xyzw: np.ndarray


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The product a * b of two quaternions (x, y, z, w), pinocchio's (Eigen's): b's rotation, then a's."""
    return np.array((pin.Quaternion(a) * pin.Quaternion(b)).coeffs())


_IDENTITY = FramePose(np.eye(4), np.array([0.0, 0.0, 0.0, 1.0]))


def tree_poses(lab_tf: dict[str, Topic], frames: Any, snapshot: Any) -> dict[str, tuple[FramePose, str]]:
    """Every frame of the transforms /tf and /tf_static carry now (`lab_tf`: the lab's own topics
    of them, with the programs' frames; `frames`, the programs' frames alone where the lab has none):
    its pose in its tree's root frame, and that root. A frame below a loop is in no tree."""
    edges: dict[str, tuple[str, FramePose]] = {}  # child -> (parent, child's pose in the parent)
    for name, static in TF_TOPICS.items():
        topic = lab_tf.get(name)  # absent in a lab started to replay bags: the programs' frames alone
        transforms = topic.build(snapshot)["transforms"] if topic is not None else frames.transforms(static)
        for t in transforms:
            edges[t["child_frame_id"].strip("/")] = (
                t["header"]["frame_id"].strip("/"),
                FramePose(*transform_pose(t["transform"])),
            )
    placed: dict[str, tuple[FramePose, str]] = {}
    unplaced: set[str] = set()  # frames in a loop or below one (each walked once: linear in the frames)
    for start in edges:
        chain, on_chain, frame = [], set(), start
        while frame not in placed and frame in edges and frame not in on_chain and frame not in unplaced:
            chain.append(frame)
            on_chain.add(frame)
            frame = edges[frame][0]
        if frame in on_chain or frame in unplaced:
            unplaced |= on_chain
            continue  # a loop
        pose, root = placed.setdefault(frame, (_IDENTITY, frame))  # known, or a root
        for child in reversed(chain):
            edge = edges[child][1]
            pose = FramePose(pose.matrix @ edge.matrix, _product(pose.rotation_xyzw, edge.rotation_xyzw))
            placed[child] = (pose, root)
    return placed


def relative(poses: dict[str, tuple[FramePose, str]], target: str, source: str) -> FramePose | None:
    """The source frame's pose in the target frame; None when either is in no tree or not in one tree.
    Its rotation is the target's inverse times the source's, as tf2 composes a path through a common
    frame (the inverse of a unit quaternion: its conjugate)."""
    if source not in poses or target not in poses or poses[source][1] != poses[target][1]:
        return None
    (target_pose, _), (source_pose, _) = poses[target], poses[source]
    conjugate = np.array(pin.Quaternion(target_pose.rotation_xyzw).conjugate().coeffs())
    return FramePose(
        np.linalg.solve(target_pose.matrix, source_pose.matrix), _product(conjugate, source_pose.rotation_xyzw)
    )


def _frame_name(name: Any, field_name: str) -> str:
    if not isinstance(name, str) or not name.strip().strip("/") or len(name) > 256:
        raise ValueError(f"'{field_name}' must be a frame name like panda_link8")
    return name.strip().strip("/")


def _request(args: dict) -> tuple[list[str], str, float]:
    """(source frames, target frame, rate Hz) of a RepublishTFs request or a TFSubscription goal;
    ValueError naming the field."""
    sources = args.get("source_frames", [])
    if not isinstance(sources, list) or len(sources) > MAX_SOURCES:
        raise ValueError(f"'source_frames' must be a list of frame names (at most {MAX_SOURCES})")
    sources = [_frame_name(name, "source_frames") for name in sources]
    target = _frame_name(args.get("target_frame", tf.WORLD), "target_frame")
    rate = args.get("rate", 10.0)
    if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not math.isfinite(rate) or rate <= 0:
        raise ValueError("'rate' must be a positive number (Hz)")
    return sources, target, min(float(rate), MAX_RATE_HZ)


# --- the service ----------------------------------------------------------------------------------
def republish(caller: Any, args: dict) -> dict:
    """Answer the service for `caller` (a client's call capability: its bridge, what goes with it):
    a new topic of the transforms, named in the response; it goes with the caller's client."""
    name, close = caller.bridge.tf.republish(caller.session, args)
    caller.on_close.append(close)
    return {"topic_name": name}


# --- the action -----------------------------------------------------------------------------------
@dataclass
class Pair:
    """One source frame of a goal (upstream's TFPair): what it last sent, to send only a change."""

    source: str
    sent: np.ndarray | None = None

    def moved(self, now: np.ndarray, trans_thres_m: float, angular_thres_rad: float) -> bool:
        """Whether `now` is to be sent: never sent, a threshold 0, or beyond one. The turn is measured
        as upstream measures it, tf's Quaternion::angle between the two rotations: half the angle of
        the rotation from one to the other."""
        if self.sent is None or trans_thres_m == 0.0 or angular_thres_rad == 0.0:
            return True
        if float(np.linalg.norm(now[:3, 3] - self.sent[:3, 3])) > trans_thres_m:
            return True
        turn = now[:3, :3] @ self.sent[:3, :3].T  # the rotation between the two, its angle from its trace
        angle = math.acos(max(-1.0, min(1.0, (float(np.trace(turn)) - 1.0) / 2.0)))
        return angle / 2.0 > angular_thres_rad


@dataclass
class Goal:
    goal_id: dict  # actionlib_msgs/GoalID as the client sent it
    session: Any
    target: str
    pairs: list[Pair]
    trans_thres_m: float
    angular_thres_rad: float
    period_s: float
    status: int = ACTIVE
    text: str = ""
    ended_at: float = math.inf  # loop time
    task: asyncio.Task | None = field(default=None, repr=False)


def _ros1_header(time_s: float, seq: int, frame_id: str = "") -> dict:
    secs = int(time_s)
    return {"seq": seq, "stamp": {"secs": secs, "nsecs": int(round((time_s - secs) * 1e9))}, "frame_id": frame_id}


def _object(message: dict, key: str) -> dict:
    """message[key] when it is a JSON object, else an empty one (its fields then take their defaults)."""
    value = message.get(key)
    return value if isinstance(value, dict) else {}


def _stamp_s(goal_id: dict) -> float:
    stamp = _object(goal_id, "stamp")
    parts = [stamp.get("secs", stamp.get("sec", 0)), stamp.get("nsecs", stamp.get("nanosec", 0))]
    if any(isinstance(p, bool) or not isinstance(p, (int, float)) or not math.isfinite(p) for p in parts):
        raise ValueError("'goal_id.stamp' must be a time {secs, nsecs}")
    return float(parts[0]) + float(parts[1]) * 1e-9


class TFSubscriptionServer:
    """The tf2_web_republisher action's server: the lab's node on the action's five topics."""

    def __init__(self, lab: Any, topics: TopicsLike, frames: FramesLike) -> None:
        self.lab, self.lab_topics, self.frames = lab, topics, frames
        self.goals: dict[str, Goal] = {}  # goal id -> goal (ended ones kept ENDED_KEPT_S for the status array)
        self.topics = {
            "goal": f"{ACTION}/goal",
            "cancel": f"{ACTION}/cancel",
            "status": f"{ACTION}/status",
            "feedback": f"{ACTION}/feedback",
            "result": f"{ACTION}/result",
        }
        types = {
            "goal": "tf2_web_republisher/TFSubscriptionActionGoal",
            "cancel": "actionlib_msgs/GoalID",
            "status": "actionlib_msgs/GoalStatusArray",
            "feedback": "tf2_web_republisher/TFSubscriptionActionFeedback",
            "result": "tf2_web_republisher/TFSubscriptionActionResult",
        }
        for key, name in self.topics.items():
            topics.add_lab_node_topic(name, types[key])
        self._seq = itertools.count(1)
        self._status_task: asyncio.Task | None = None
        self.owners: dict[str, Any] = {}  # a /republish_tfs topic -> the session that asked for it
        self._tree: tuple[Any, int, dict[str, tuple[FramePose, str]]] | None = (
            None  # (snapshot, frames' version, poses)
        )

    def tree(self, snapshot: Any) -> tuple[Any, dict[str, tuple[FramePose, str]]]:
        """(the snapshot it was built at, tree_poses) for every goal and republished topic: built once
        a period (1 / MAX_RATE_HZ of simulated time, either way: a reset sends it back) while the
        programs' frames stay, not once per request or goal."""
        kept, version = self._tree, self.frames.version
        if (
            kept is None
            or kept[1] != version
            or not (kept[0] is snapshot or abs(snapshot.time - kept[0].time) < 1.0 / MAX_RATE_HZ)
        ):
            kept = self._tree = (snapshot, version, tree_poses(self._lab_tf(), self.frames, snapshot))
        return kept[0], kept[2]

    def _lab_tf(self) -> dict[str, Topic]:
        """The lab's own /tf and /tf_static topics (none in a lab started to replay bags)."""
        found = {name: self.lab_topics.lab_topic(name) for name in TF_TOPICS}
        return {name: topic for name, topic in found.items() if topic is not None}

    def republish(self, session: Any, args: dict) -> tuple[str, Callable[[], None]]:
        """/republish_tfs for `session`: the name of a new topic of the transforms, and what removes
        it (when its client goes); ServiceFailure with the reason it cannot."""
        try:
            sources, target, rate = _request(args)
        except ValueError as bad:
            raise ServiceFailure(f"republish_tfs: {bad}") from None
        known = self.tree(self.lab.snapshot())[1]
        for name in [*sources, target]:
            if name not in known:
                raise ServiceFailure(
                    f"republish_tfs: frame '{name[:80]}' does not exist (frames: {', '.join(sorted(known))})"
                )
        if self.subscriptions() >= MAX_SUBSCRIPTIONS:
            raise ServiceFailure(f"republish_tfs: {MAX_SUBSCRIPTIONS} republished topics and goals exist already")
        if self.held_by(session) >= MAX_CLIENT_TF_REPUBLISHED:
            raise ServiceFailure(
                f"republish_tfs: this client holds {MAX_CLIENT_TF_REPUBLISHED} republished topics and goals already "
                "(the limit per client)"
            )

        def build(snapshot: Any) -> dict:
            at, poses = self.tree(snapshot)  # a frame whose program went: left out
            found = ((source, relative(poses, target, source)) for source in sources)
            return {
                "transforms": [
                    tf.relative_stamped(at, target, s, pose.matrix, pose.rotation_xyzw)
                    for s, pose in found
                    if pose is not None
                ]
            }

        name = f"/tf_repub_{next(_NUMBERS)}"
        self.lab_topics.add_topic(Topic(name, ARRAY_TYPE, build), min_period_s=1.0 / rate)
        self.owners[name] = session

        def close() -> None:
            self.lab_topics.remove_topic(name)
            self.owners.pop(name, None)

        return name, close

    def held_by(self, session: Any) -> int:
        """Republished topics and active goals `session` holds (MAX_CLIENT_TF_REPUBLISHED)."""
        goals = sum(1 for g in self.goals.values() if g.session is session and g.status == ACTIVE)
        return goals + sum(1 for owner in self.owners.values() if owner is session)

    @property
    def inputs(self) -> tuple[str, str]:
        return self.topics["goal"], self.topics["cancel"]

    def subscriptions(self) -> int:
        """Republished topics and active goals, all clients together (MAX_SUBSCRIPTIONS)."""
        goals = sum(1 for g in self.goals.values() if g.status == ACTIVE)
        return goals + sum(1 for name in self.lab_topics.sampled_names() if name.startswith("/tf_repub_"))

    def start(self) -> None:
        """The status array at 5 Hz, from the first client on (called on the server's event loop)."""
        if self._status_task is None or self._status_task.done():
            self._status_task = asyncio.ensure_future(self._publish_status())

    # --- what clients publish ---
    def take(self, session: Any, topic: str, msg: dict) -> None:
        """A goal or a cancel `session` published; BadFrame naming the field for one that is refused."""
        if topic == self.topics["goal"]:
            self._goal(session, msg)
        else:
            self._cancel(msg)

    def _goal(self, session: Any, msg: dict) -> None:
        goal_id = _object(msg, "goal_id")
        id_ = goal_id.get("id", "")
        if not isinstance(id_, str) or len(id_) > 256:
            raise BadFrame(f"publish {self.topics['goal']}: 'goal_id.id' must be a string")
        if not id_:  # as actionlib's server names a goal sent without an id
            id_ = f"{ACTION}-{next(self._seq)}-{self.lab.snapshot().time:.3f}"
            goal_id = {**goal_id, "id": id_}
        body = _object(msg, "goal")
        try:
            sources, target, rate = _request(body)
            thresholds = [body.get("trans_thres", 0.0), body.get("angular_thres", 0.0)]
            if any(isinstance(t, bool) or not isinstance(t, (int, float)) or not t >= 0 for t in thresholds):
                raise ValueError("'trans_thres' (m) and 'angular_thres' (rad) must be numbers >= 0")
            if self.subscriptions() >= MAX_SUBSCRIPTIONS:
                raise ValueError(f"{MAX_SUBSCRIPTIONS} republished topics and goals exist already")
            if self.held_by(session) >= MAX_CLIENT_TF_REPUBLISHED:
                raise ValueError(
                    f"this client holds {MAX_CLIENT_TF_REPUBLISHED} republished topics and goals already "
                    "(the limit per client)"
                )
        except ValueError as bad:
            self._end(Goal(goal_id, session, "", [], 0.0, 0.0, 1.0), REJECTED, str(bad))
            raise BadFrame(f"publish {self.topics['goal']}: goal rejected: {bad}") from None
        old = self.goals.get(id_)
        if old is not None and old.status == ACTIVE:
            raise BadFrame(f"publish {self.topics['goal']}: goal {id_[:80]} is active already")
        goal = Goal(
            goal_id, session, target, [Pair(s) for s in sources], float(thresholds[0]), float(thresholds[1]), 1.0 / rate
        )
        self.goals[id_] = goal
        goal.task = asyncio.ensure_future(self._feed(goal))

    def drop(self, session: Any) -> None:
        """`session`'s client is gone: its active goals end PREEMPTED (capabilities/publish.py's finish)."""
        for goal in [g for g in self.goals.values() if g.session is session and g.status == ACTIVE]:
            self._end(goal, PREEMPTED, "its client disconnected")

    def _cancel(self, msg: dict) -> None:
        """actionlib's cancel rules: an id cancels that goal; no id and no stamp, every goal; a stamp,
        every goal stamped at or before it."""
        id_ = msg.get("id", "")
        try:
            before = _stamp_s(msg)
            ids = [
                key
                for key, goal in self.goals.items()
                if goal.status == ACTIVE
                and (
                    (id_ and key == id_)
                    or (not id_ and before == 0.0)
                    or (before > 0.0 and _stamp_s(goal.goal_id) <= before)
                )
            ]
        except ValueError as bad:
            raise BadFrame(f"publish {self.topics['cancel']}: {bad}") from None
        for key in ids:
            self._end(self.goals[key], PREEMPTED, "cancelled")

    # --- what the lab publishes ---
    def _offer(self, key: str, msg: dict) -> None:
        self.lab_topics.deliver(self.topics[key], msg)

    def _status(self, goal: Goal) -> dict:
        return {"goal_id": goal.goal_id, "status": goal.status, "text": goal.text}

    def _end(self, goal: Goal, status: int, text: str) -> None:
        if goal.status != ACTIVE:
            return
        goal.status, goal.text = status, text
        goal.ended_at = asyncio.get_running_loop().time()
        if goal.task is not None:
            goal.task.cancel()
        self.goals.setdefault(goal.goal_id.get("id", ""), goal)
        ended = [k for k, g in self.goals.items() if g.status != ACTIVE]
        for key in ended[: max(0, len(ended) - MAX_SUBSCRIPTIONS)]:  # a flood of rejected goals: the oldest go
            del self.goals[key]
        time_s = self.lab.snapshot().time
        self._offer(
            "result", {"header": _ros1_header(time_s, next(self._seq)), "status": self._status(goal), "result": {}}
        )

    async def _feed(self, goal: Goal) -> None:
        """The goal's changed transforms as its feedback, every period, while it is active."""
        loop = asyncio.get_running_loop()
        due = loop.time()
        while goal.status == ACTIVE:
            snapshot, poses = self.tree(self.lab.snapshot())
            transforms = []
            for pair in goal.pairs:
                now = relative(poses, goal.target, pair.source)
                if now is not None and pair.moved(now.matrix, goal.trans_thres_m, goal.angular_thres_rad):
                    pair.sent = now.matrix
                    stamped = tf.relative_stamped(snapshot, goal.target, pair.source, now.matrix, now.rotation_xyzw)
                    transforms.append(_ros1_transform(stamped))
            if transforms:
                header = _ros1_header(snapshot.time, next(self._seq))
                self._offer(
                    "feedback", {"header": header, "status": self._status(goal), "feedback": {"transforms": transforms}}
                )
            due = max(due + goal.period_s, loop.time())
            await asyncio.sleep(due - loop.time())

    async def _publish_status(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            now = loop.time()
            for key in [k for k, g in self.goals.items() if now - g.ended_at > ENDED_KEPT_S]:
                del self.goals[key]
            if self.lab_topics.subscribed(self.topics["status"]):
                header = _ros1_header(self.lab.snapshot().time, next(self._seq))
                self._offer("status", {"header": header, "status_list": [self._status(g) for g in self.goals.values()]})
            await asyncio.sleep(STATUS_PERIOD_S)


def _ros1_transform(stamped: dict) -> dict:
    """A geometry_msgs/TransformStamped with ROS 1's header (seq; stamp in secs, nsecs)."""
    stamp = stamped["header"]["stamp"]
    header = _ros1_header(stamp["sec"] + stamp["nanosec"] * 1e-9, 0, stamped["header"]["frame_id"])
    return {**stamped, "header": header}
