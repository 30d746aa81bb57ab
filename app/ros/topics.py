"""Topics: the latest message of each, built from the loop's snapshot, shaped like the ROS message
it mirrors. One declaration per topic: name, type, builder(snapshot) -> dict.

A stream (`/topics/{name}/stream?rate=HZ`, WebSocket) sends the newest message at most `rate`
times a second. It only reads snapshots, so it never blocks the simulation; a client that reads
slowly gets fewer, always fresh, messages (the ones it could not take are dropped)."""
import asyncio
from dataclasses import dataclass
from typing import Callable

import numpy as np
import pinocchio as pin
from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect

from sim.world import Snapshot

JOINT_NAMES = [f"panda_joint{i}" for i in range(1, 8)]


def header(s: Snapshot, frame_id: str) -> dict:
    sec = int(s.time)
    return {"stamp": {"sec": sec, "nanosec": int(round((s.time - sec) * 1e9))}, "frame_id": frame_id}


def vector3(v) -> dict:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def pose(position, rotation) -> dict:
    q = pin.Quaternion(np.asarray(rotation))  # ROS orders x, y, z, w
    return {"position": vector3(position), "orientation": {"x": q.x, "y": q.y, "z": q.z, "w": q.w}}


def wrench_stamped(s: Snapshot) -> dict:
    return {"header": header(s, "panda_K"), "wrench": {"force": vector3(s.wrench_ee[:3]), "torque": vector3(s.wrench_ee[3:])}}


def joint_state(s: Snapshot) -> dict:
    return {"header": header(s, ""), "name": JOINT_NAMES, "position": s.q.tolist(), "velocity": s.qdot.tolist(), "effort": []}


def twist(s: Snapshot) -> dict:
    return {"linear": vector3(s.twist_command[:3]), "angular": vector3(s.twist_command[3:])}


def object_pose(s: Snapshot) -> dict:
    return {"header": header(s, "panda_link0"), "pose": pose(s.box_position, s.box_rotation)}


def hand_pose(s: Snapshot) -> dict:
    return {"header": header(s, "panda_link0"), "pose": pose(s.palm_position, s.palm_rotation)}


def contact_state(s: Snapshot) -> dict:
    plate, palm = s.plate, s.palm
    mu = s.lifting.mu
    return {
        "header": header(s, "panda_link0"),
        "normal_force": plate.normal_force,
        "tangential_force": vector3(plate.tangential_force),
        "friction_ratio": plate.friction_ratio / mu if mu > 0 else 0.0,
        "centre_of_pressure": {"x": float(plate.centre_of_pressure[0]), "y": float(plate.centre_of_pressure[1])},
        "robot_contact": plate.points_in_contact > 0,
        "robot_slipping": plate.points_slipping > 0,
        "human_contact": palm.points_in_contact > 0,
        "human_slipping": palm.points_slipping > 0,
        "human_normal_force": palm.normal_force,
    }


def lifting_state(s: Snapshot) -> dict:
    return {
        "header": header(s, ""),
        "started": s.lifting.running,
        "f_n_min": s.lifting.f_n_min,
        "f_n_max": s.lifting.f_n_max,
        "error": s.error or "",
        "human_phase": s.human_phase,
    }


def trial_outcome(s: Snapshot) -> dict:
    """The scripted participant's trial (sim/procedures/monitor.py): state none, running,
    succeeded, failed or abandoned; the figures of the experiment's table (N, m, s)."""
    t = s.trial
    return {"header": header(s, ""), "state": t.state, "participant": t.participant, "duration": t.duration,
            "f_n_min": t.f_n_min, "f_n_max": t.f_n_max, "max_friction_ratio": t.max_friction_ratio, "slip": t.slip,
            "reason": t.reason}


@dataclass(frozen=True)
class Topic:
    name: str
    type: str
    build: Callable[[Snapshot], dict]


TOPICS = [
    Topic("/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", wrench_stamped),
    Topic("/joint_states", "sensor_msgs/JointState", joint_state),
    Topic("/cartesian_velocity_controller/command", "geometry_msgs/Twist", twist),
    Topic("/object_pose", "geometry_msgs/PoseStamped", object_pose),
    Topic("/human_hand_pose", "geometry_msgs/PoseStamped", hand_pose),
    Topic("/contact_state", "hri_lab/ContactState", contact_state),
    Topic("/lifting_state", "hri_lab/LiftingState", lifting_state),
    Topic("/trial", "hri_lab/TrialOutcome", trial_outcome),
]


def router(lab) -> APIRouter:
    by_name = {t.name: t for t in TOPICS}
    r = APIRouter(tags=["topics"])

    @r.get("/topics", summary="Topics with their types (ros2 topic list -t)")
    def list_topics() -> list[dict]:
        return [{"name": t.name, "type": t.type} for t in TOPICS]

    @r.get("/topics/{name:path}", summary="Latest message of a topic (ros2 topic echo --once)")
    def latest(name: str) -> dict:
        topic = by_name.get("/" + name.lstrip("/"))
        if topic is None:
            raise HTTPException(404, f"topic '/{name.lstrip('/')}' does not exist")
        return topic.build(lab.snapshot())

    @r.websocket("/topics/{name:path}/stream")
    async def stream(websocket: WebSocket, name: str, rate: float = Query(10.0, gt=0.0, le=MAX_RATE_HZ)) -> None:
        topic = by_name.get("/" + name.lstrip("/"))
        if topic is None:
            await websocket.close(code=1008, reason=f"topic '/{name.lstrip('/')}' does not exist")
            return
        await websocket.accept()
        period = 1.0 / rate
        loop = asyncio.get_running_loop()
        next_send = loop.time()
        last_time = None
        try:
            while True:
                snapshot = lab.snapshot()
                if snapshot.time != last_time:  # one message per new simulation state
                    last_time = snapshot.time
                    await websocket.send_json(topic.build(snapshot))
                next_send = max(next_send + period, loop.time())  # behind: skip, never queue up
                await asyncio.sleep(next_send - loop.time())
        except (WebSocketDisconnect, RuntimeError):
            return

    return r


MAX_RATE_HZ = 1000.0
