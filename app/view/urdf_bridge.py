"""What `hri-lab urdf view` serves beside its 3D view: the student's robot as a small ROS system of
its own, as `roslaunch urdf_tutorial display.launch` makes one — the `/robot_description`
parameter (the file's text) and `/joint_states` (sensor_msgs/JointState from the sliders, as
joint_state_publisher publishes it: at PUBLISH_RATE_HZ, and at once when a slider moves).

Its own server, not the lab's: the lab's `/joint_states` and `/robot_description` are the Panda's.
On one port (127.0.0.1, the lab's cross-site checks):

  WS  /                        rosbridge v2, the subset a viewer's client needs: subscribe /
                               unsubscribe `/joint_states`; call_service `/rosapi/get_param`,
                               `has_param`, `get_param_names`, `topics`, `topic_type` (roslibpy's
                               `Param('/robot_description').get()`, `Topic('/joint_states', ...)`)
  GET /robot_description       the URDF text (application/xml)
  GET /topics                  [{"name": "/joint_states", "type": "sensor_msgs/JointState"}]
  GET /topics/joint_states     the latest message; WS /topics/joint_states/stream?rate= the stream
                               (so `hri-lab topic echo /joint_states --url URL` reads it)
"""

from __future__ import annotations

import asyncio
import json
from typing import Any

from fastapi import FastAPI, HTTPException, Query, WebSocket, WebSocketDisconnect
from fastapi.responses import Response

from app.rosbridge.protocol import MAX_FRAME, BadFrame, field, name_field, parse, status
from app.security import SiteGuard
from app.view.urdf_view import JointStates

PUBLISH_RATE_HZ = 10.0  # joint_state_publisher's default `rate`
CHANGE_POLL_S = 0.02  # a moved slider is sent within this
JOINT_STATES = "/joint_states"
JOINT_STATE_TYPE = "sensor_msgs/JointState"
ROBOT_DESCRIPTION = "/robot_description"


class _Rosapi:
    """The rosapi services over the view's one parameter and one topic."""

    def __init__(self, description: str) -> None:
        self.params = {ROBOT_DESCRIPTION: description}

    def call(self, service: str, args: dict) -> dict:
        name = "/" + str(args.get("name", "")).strip("/")
        if service == "/rosapi/get_param":
            if name in self.params:
                return {"value": json.dumps(self.params[name])}
            default = args.get("default_value", args.get("default", ""))
            return {"value": default if default else "null"}
        if service == "/rosapi/has_param":
            return {"exists": name in self.params}
        if service == "/rosapi/get_param_names":
            return {"names": sorted(self.params)}
        if service == "/rosapi/topics":
            return {"topics": [JOINT_STATES], "types": [JOINT_STATE_TYPE]}
        if service == "/rosapi/topic_type":
            return {"type": JOINT_STATE_TYPE if "/" + str(args.get("topic", "")).strip("/") == JOINT_STATES else ""}
        raise BadFrame(
            f"call_service: the URDF view has no service {service} (it serves /robot_description and /joint_states)"
        )


async def _publish_loop(states: JointStates, send, rate_hz: float) -> None:
    """joint_state_publisher: the message every 1/rate_hz s, and within CHANGE_POLL_S after a slider moved."""
    loop = asyncio.get_running_loop()
    period = 1.0 / rate_hz
    sent_version, due = -1, 0.0
    while True:
        now = loop.time()
        if states.version != sent_version or now >= due:
            sent_version, due = states.version, now + period
            await send(states.message())
        await asyncio.sleep(min(CHANGE_POLL_S, period))


async def _rosbridge(websocket: WebSocket, states: JointStates, rosapi: _Rosapi) -> None:
    await websocket.accept()
    lock = asyncio.Lock()
    streams: dict[str, asyncio.Task] = {}

    async def send(frame: dict) -> None:
        async with lock:
            await websocket.send_text(json.dumps(frame))

    def subscribe(message: dict) -> None:
        topic = name_field(message, "topic")
        if topic != JOINT_STATES:
            raise BadFrame(f"subscribe: the URDF view publishes {JOINT_STATES} only, not {topic}")
        wanted = field(message, "type", str, "") or JOINT_STATE_TYPE
        if wanted.replace("/msg/", "/") != JOINT_STATE_TYPE:
            raise BadFrame(f"subscribe: topic {topic} is of type {JOINT_STATE_TYPE}, not {wanted}")
        throttle_ms = field(message, "throttle_rate", (int, float), 0)
        rate = PUBLISH_RATE_HZ if not throttle_ms else min(PUBLISH_RATE_HZ, 1000.0 / max(1.0, float(throttle_ms)))
        if topic not in streams:

            async def publish(msg: dict) -> None:
                await send({"op": "publish", "topic": topic, "msg": msg})

            streams[topic] = asyncio.create_task(_publish_loop(states, publish, rate))

    try:
        while True:
            text = await websocket.receive_text()
            id_, op, service = None, None, None
            try:
                if len(text) > MAX_FRAME:
                    raise BadFrame(f"frame of {len(text)} characters refused (limit {MAX_FRAME})")
                message = parse(text)
                id_, op = message.get("id"), message["op"]
                if op == "subscribe":
                    subscribe(message)
                elif op == "unsubscribe":
                    task = streams.pop(name_field(message, "topic"), None)
                    if task is not None:
                        task.cancel()
                elif op == "call_service":
                    service = name_field(message, "service")
                    args = field(message, "args", (dict, list), {})
                    values = rosapi.call(service, args if isinstance(args, dict) else {})
                    await send(
                        {"op": "service_response", "service": service, "id": id_, "values": values, "result": True}
                    )
                elif op in ("advertise", "unadvertise", "publish"):
                    raise BadFrame(f"{op}: the URDF view only publishes {JOINT_STATES} (from its sliders)")
                else:
                    raise BadFrame(f"op '{op}' is not served by the URDF view (subscribe, unsubscribe, call_service)")
            except BadFrame as bad:
                if service is not None:  # a call gets its answer (a failed one), as rosbridge answers
                    await send(
                        {"op": "service_response", "service": service, "id": id_, "values": str(bad), "result": False}
                    )
                else:
                    await send(status("error", str(bad), id_))
    except Exception:  # noqa: BLE001 - a broken connection (or a binary frame) ends this session only
        pass
    finally:
        for task in streams.values():
            task.cancel()


def urdf_app(states: JointStates, description: str, view_url: str) -> Any:
    """The ASGI app (behind the lab's cross-site guard) of one viewed URDF."""
    app = FastAPI(title="hri-lab urdf view", description="A URDF's /robot_description and /joint_states.")
    rosapi = _Rosapi(description)

    @app.websocket("/")
    async def rosbridge(websocket: WebSocket) -> None:
        """rosbridge v2: /joint_states and /robot_description."""
        await _rosbridge(websocket, states, rosapi)

    @app.get("/", summary="What this server serves")
    def index() -> dict:
        return {"view": view_url, "topics": [JOINT_STATES], "params": [ROBOT_DESCRIPTION]}

    @app.get(ROBOT_DESCRIPTION, summary="The URDF's text (the /robot_description parameter)")
    def robot_description() -> Response:
        return Response(description, media_type="application/xml")

    @app.get("/topics", summary="The topics (ros2 topic list -t)")
    def topics() -> list[dict]:
        return [{"name": JOINT_STATES, "type": JOINT_STATE_TYPE}]

    def known(name: str) -> None:
        if "/" + name.strip("/") != JOINT_STATES:
            raise HTTPException(404, f"topic '/{name.strip('/')}' does not exist: the URDF view has {JOINT_STATES}")

    @app.get("/topics/{name:path}", summary="The latest message of a topic")
    def latest(name: str) -> dict:
        known(name)
        return states.message()

    @app.websocket("/topics/{name:path}/stream")
    async def stream(websocket: WebSocket, name: str, rate: float = Query(10.0, gt=0.0, le=1000.0)) -> None:
        if "/" + name.strip("/") != JOINT_STATES:
            await websocket.close(code=1008, reason=f"no topic /{name.strip('/')}")
            return
        await websocket.accept()
        try:
            await _publish_loop(states, lambda msg: websocket.send_text(json.dumps(msg)), min(rate, PUBLISH_RATE_HZ))
        except (WebSocketDisconnect, RuntimeError):
            pass

    return SiteGuard(app, bound_host="127.0.0.1")
