"""/topics: the latest message of a topic (GET) and a rate-limited stream of them (WebSocket).

A stream (`/topics/{name}/stream?rate=HZ`) sends the newest message at most `rate` times a second.
It only reads snapshots, so it never blocks the simulation; a client that reads slowly gets fewer,
always fresh, messages (the ones it could not take are dropped). `rate` is 0.1 to 1000 Hz; a stream
ends as soon as its client goes (it listens for the close while it waits). /rosout is a log, not a
state: its stream sends every line as it comes (app/ros/rosout.py)."""

import asyncio
from collections import deque

from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect

from sim.messages import Topic
from sim.sampling import due

from app.api.camera import current_frame
from app.api.deps import LabDep
from app.api.responses import finite_or_null
from app.ros import rosout
from app.ros.names import absolute
from app.runtime.camera_process import IMAGE, image_message

MIN_RATE_HZ, MAX_RATE_HZ = 0.1, 1000.0
MAX_QUEUED = 1000  # /rosout lines waiting for a slow client


def router(topics: list[Topic]) -> APIRouter:
    by_name = {t.name: t for t in topics}
    r = APIRouter(tags=["topics"])

    @r.get("/topics", summary="Topics with their types (ros2 topic list -t)")
    def list_topics() -> list[dict]:
        return [{"name": t.name, "type": t.type} for t in topics] + [{"name": rosout.TOPIC, "type": rosout.TYPE}]

    @r.get("/topics/{name:path}", summary="Latest message of a topic (ros2 topic echo --once)")
    def latest(name: str, lab: LabDep) -> dict:
        if absolute(name) == rosout.TOPIC:
            lines = lab.rosout.recent()
            if not lines:
                raise HTTPException(404, f"no line on {rosout.TOPIC} yet")
            return lines[-1].message()
        topic = by_name.get(absolute(name))
        if topic is None:
            raise HTTPException(404, f"topic '{absolute(name)}' does not exist")
        if topic.name == IMAGE and lab.camera is not None:  # the camera's image of the current pose (app/api/camera.py)
            return image_message(current_frame(lab))
        return finite_or_null(topic.build(lab.snapshot()))

    @r.websocket("/topics/{name:path}/stream")
    async def stream(
        websocket: WebSocket, name: str, lab: LabDep, rate: float = Query(10.0, ge=MIN_RATE_HZ, le=MAX_RATE_HZ)
    ) -> None:
        if absolute(name) == rosout.TOPIC:
            return await _log_stream(websocket, lab)
        topic = by_name.get(absolute(name))
        if topic is None:
            await websocket.close(code=1008, reason=f"topic '{absolute(name)}' does not exist")
            return
        await websocket.accept()
        period = 1.0 / rate
        gone = asyncio.ensure_future(client_gone(websocket))
        try:
            if topic.name == IMAGE and lab.camera is not None:
                with lab.camera.wants(period):
                    await _send_each_new_image(websocket, lab, period, gone)
                return
            with lab.needs(period):
                await _send_each_new_state(websocket, topic, lab, period, gone)
        except (WebSocketDisconnect, RuntimeError):
            return
        finally:
            gone.cancel()

    return r


async def _send_each_new_state(websocket: WebSocket, topic, lab, period: float, gone: asyncio.Future) -> None:
    """The newest state, at most one message per `period` s of the wall clock and of simulated time
    (rosbridge's minimum gap; half a control period of slack), paced by the wall clock: behind, it
    skips, it never queues up."""
    loop = asyncio.get_running_loop()
    next_send = loop.time()
    last_time = None
    while not gone.done():
        snapshot = lab.snapshot()
        if due(last_time, snapshot.time, period):
            last_time = snapshot.time
            await websocket.send_json(finite_or_null(topic.build(snapshot)))
        next_send = max(next_send + period, loop.time())
        await asyncio.wait([gone], timeout=next_send - loop.time())


async def _send_each_new_image(websocket: WebSocket, lab, period: float, gone: asyncio.Future) -> None:
    """/image_raw: each new image of the camera, at least `period` s of simulated time apart."""
    camera, seen, last = lab.camera, lab.camera.number, None
    while not gone.done():
        if camera.number != seen:
            frame = camera.latest()
            if frame is not None and due(last, frame.time, period):
                seen, last = frame.number, frame.time
                await websocket.send_json(image_message(frame))
        await asyncio.wait([gone], timeout=0.005)


async def client_gone(websocket: WebSocket) -> None:
    """Returns when the client closes the WebSocket (what it sends meanwhile is ignored)."""
    while True:
        message = await websocket.receive()
        if message["type"] == "websocket.disconnect":
            return


async def _log_stream(websocket: WebSocket, lab) -> None:
    """/rosout: every line from now on, in order (a log is not sampled; `rate` does not apply); a
    client that cannot keep up loses the oldest of MAX_QUEUED waiting lines."""
    await websocket.accept()
    loop = asyncio.get_running_loop()
    queue: deque = deque(maxlen=MAX_QUEUED)
    ready = asyncio.Event()

    def offer(line) -> None:
        queue.append(line)
        ready.set()

    stop = lab.rosout.listen(lambda line: loop.call_soon_threadsafe(offer, line))
    gone = asyncio.ensure_future(client_gone(websocket))
    try:
        while not gone.done():
            waiting = asyncio.ensure_future(ready.wait())
            await asyncio.wait([gone, waiting], return_when=asyncio.FIRST_COMPLETED)
            waiting.cancel()
            ready.clear()
            while queue:
                await websocket.send_json(queue.popleft().message())
    except (WebSocketDisconnect, RuntimeError):
        return
    finally:
        stop()
        gone.cancel()
