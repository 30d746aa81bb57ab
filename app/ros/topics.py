"""Topics: the latest message of each, built from the loop's snapshot, shaped like the ROS message
it mirrors. The topics are declared in sim/messages.py (recordings store the same messages).

A stream (`/topics/{name}/stream?rate=HZ`, WebSocket) sends the newest message at most `rate`
times a second. It only reads snapshots, so it never blocks the simulation; a client that reads
slowly gets fewer, always fresh, messages (the ones it could not take are dropped)."""
import asyncio

from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect

from sim.messages import TOPICS, Topic, wrench_stamped  # noqa: F401 - re-exported


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
