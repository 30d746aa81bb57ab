"""What connection headers cost a relayed node topic: one client publishes std_msgs/String on a
node topic as fast as the lab takes it, with headers in its advertise; two subscribers read it at
throttle_rate 0, one asking for connection headers (rospy's) and one not (rosbridge's frame), in
turns of --seconds each; the messages each received per second, the median of --rounds.

    .venv/bin/python -m bench.relay_headers [--seconds 3] [--rounds 5]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import statistics
import time

from websockets.asyncio.client import connect

from app.serving.launch import running_server

TOPIC = "/relay_bench"


async def publisher(url: str, stop: asyncio.Event) -> None:
    async with connect(url, max_size=None) as ws:
        await ws.send(json.dumps({"op": "node", "name": "/relay_talker"}))
        headers = {"cookies": "oreo", "latching": "0"}
        await ws.send(json.dumps({"op": "advertise", "topic": TOPIC, "type": "std_msgs/String", "headers": headers}))
        n = 0
        while not stop.is_set():
            n += 1
            await ws.send(json.dumps({"op": "publish", "topic": TOPIC, "msg": {"data": f"hello {n}"}}))
            await asyncio.sleep(0)


async def rate(url: str, asks: bool, seconds: float) -> tuple[float, bool]:
    """Messages per second one subscriber received (asking for headers or not), and whether every
    one of them carried a connection header (a lab before the extension sends none)."""
    async with connect(url, max_size=None) as ws:
        frame = {"op": "subscribe", "topic": TOPIC, "type": "std_msgs/String", "queue_length": 1000}
        if asks:
            frame["connection_header"] = True
        await ws.send(json.dumps(frame))
        stop = asyncio.Event()
        talker = asyncio.ensure_future(publisher(url, stop))
        received, start, all_headers = 0, None, True
        try:
            while True:
                message = json.loads(await asyncio.wait_for(ws.recv(), 30))
                if message.get("op") != "publish":
                    continue
                all_headers = all_headers and "connection_header" in message
                if start is None:
                    start = time.perf_counter()
                    continue
                received += 1
                if time.perf_counter() - start >= seconds:
                    return received / (time.perf_counter() - start), all_headers
        finally:
            stop.set()
            await talker


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    with running_server("--view", "none") as server:
        url = f"ws://127.0.0.1:{server.port}/"
        rates: dict[bool, list[float]] = {False: [], True: []}
        headers: dict[bool, bool] = {False: True, True: True}
        for _ in range(args.rounds):
            for asks in (False, True):
                per_second, all_headers = asyncio.run(rate(url, asks, args.seconds))
                rates[asks].append(per_second)
                headers[asks] = headers[asks] and all_headers
    for asks, label in ((False, "no header asked"), (True, "connection_header asked")):
        values = rates[asks]
        carried = "every frame with its header" if headers[asks] else "frames without a header"
        print(
            f"{label:24s} median {statistics.median(values):7.0f} msg/s "
            f"(min {min(values):.0f}, max {max(values):.0f}); {carried}"
        )


if __name__ == "__main__":
    main()
