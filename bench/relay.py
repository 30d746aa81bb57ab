"""A node topic relayed by the lab's rosbridge: messages/s one publisher's topic gets through to two
subscribers, in the server's own code (the real Bridge the composition root builds and real
Sessions, their WebSockets counting what is sent; no network, no client's cost), the message made
whole before it is relayed (app/rosbridge/internal/message_conversion.py) against relayed as it was
sent (the conversion replaced by nothing: the relay before it).

Per message: the publish frame parsed, the message made whole (once), queued to both subscribers'
streams, encoded once and sent to both, each message sent before the next is published (a stream
sends at most 1 kHz). CPU time of this process over `--messages` publishes; and the conversion alone
(`populate`), in µs per message.

    .venv/bin/python -m bench.relay [--messages 5000] [--rounds 3]
"""

from __future__ import annotations

import argparse
import asyncio
import functools
import gc
import json
import time
import timeit
from typing import Any
from unittest import mock

from app.lab.lab import Lab
from app.rosbridge.internal.message_conversion import populate
from app.rosbridge.session import Session
from app.serving.compose import build

# a program's own 1 kHz topic (a PoseStamped with its header, as rospy/rclpy publish it) and a ROS 1
# client's cancel (its id alone: filled)
MESSAGES = {
    "geometry_msgs/PoseStamped": {
        "header": {"stamp": {"sec": 12, "nanosec": 345000000}, "frame_id": "panda_link0"},
        "pose": {"position": {"x": 0.4, "y": 0.0, "z": 0.3}, "orientation": {"x": 1.0, "y": 0.0, "z": 0.0, "w": 0.0}},
    },
    "actionlib_msgs/GoalID": {"id": "goal_1"},
}


class Socket:
    """A WebSocket that counts what it is sent and tells when it got a message."""

    def __init__(self) -> None:
        self.scope: dict[str, Any] = {"headers": []}
        self.count = 0
        self.got = asyncio.Event()

    async def send_text(self, text: str) -> None:
        self.count += 1
        self.got.set()


async def relay(type_name: str, message: dict, count: int) -> float:
    """CPU s to relay `count` publishes of `message` to two subscribers."""
    parts = build(Lab(), replay=True)  # no lab topics: only the relay works
    sessions = []
    for _ in range(3):
        session = Session(parts.bridge, Socket())  # type: ignore[arg-type]  # a WebSocket's two members
        session.loop = asyncio.get_running_loop()
        parts.bridge.sessions.join(session)
        sessions.append(session)
    publisher, *subscribers = sessions
    for subscriber in subscribers:
        await subscriber.handle(json.dumps({"op": "subscribe", "topic": "/relayed", "type": type_name}))
    await publisher.handle(json.dumps({"op": "advertise", "topic": "/relayed", "type": type_name}))
    frame = json.dumps({"op": "publish", "topic": "/relayed", "msg": message})
    sockets: list[Socket] = [s.ws for s in subscribers]  # type: ignore[misc]
    gc.collect()  # the last round's lab collected before, not during, this one
    started = time.process_time()
    for _ in range(count):  # each message sent to both before the next (a stream sends at most 1 kHz)
        for socket in sockets:
            socket.got.clear()
        await publisher.handle(frame)
        for socket in sockets:
            await asyncio.wait_for(socket.got.wait(), 10)
    spent = time.process_time() - started
    assert [s.count for s in sockets] == [count, count]
    for session in sessions:
        for capability in list(session.capabilities.values()):
            capability.finish()
    return spent


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--messages", type=int, default=5_000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    print(f"{args.messages} publishes to two subscribers, messages/s of CPU (median of {args.rounds} rounds)")
    for type_name, message in MESSAGES.items():
        rates: dict[str, list[float]] = {"made whole": [], "as sent": []}
        for i in range(args.rounds):  # interleaved, each first in turn, so both see the same load
            for how in list(rates)[:: 1 if i % 2 == 0 else -1]:
                if how == "as sent":
                    with mock.patch("app.rosbridge.capabilities.publish.populate", lambda t, d, m: m):
                        spent = asyncio.run(relay(type_name, message, args.messages))
                else:
                    spent = asyncio.run(relay(type_name, message, args.messages))
                rates[how].append(args.messages / spent)
        line = ", ".join(f"{how}: {sorted(r)[len(r) // 2]:,.0f}" for how, r in rates.items())
        whole = functools.partial(populate, type_name, "", message)
        alone = min(timeit.repeat(whole, number=10_000, repeat=args.rounds)) / 10_000
        print(f"  {type_name}: {line}; making it whole alone: {alone * 1e6:.1f} us")


if __name__ == "__main__":
    main()
