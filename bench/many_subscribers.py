"""HTTP and the loop while many rosbridge clients subscribe at full rate (issue 33, item 5):
`clients` WebSocket clients each subscribe at throttle_rate 0 to four of the lab's 1 kHz topics
(F_ext, /joint_states, /contact_state, /lifting_state); POST /services/error_recovery is called
`calls` times in a row before and while they stream, and the loop's own figures are read from
/health. Prints the HTTP p50/p99/max alone and under the load, the messages the clients received
a second (the lab's total is capped: app/rosbridge/managers/topics.py, MAX_OUTGOING_RATE) and the
loop's rate and lateness.

    .venv/bin/python -m bench.many_subscribers [--clients 20] [--calls 300] [--seconds 10]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import threading
import time

import httpx
from websockets.asyncio.client import connect

from app.rosbridge.managers.topics import MAX_OUTGOING_RATE
from app.serving.launch import running_server
from bench import percentile

TOPICS = ("/franka_state_controller/F_ext", "/joint_states", "/contact_state", "/lifting_state")


def http_latencies(client: httpx.Client, url: str, calls: int) -> list[float]:
    out = []
    for _ in range(calls):
        started = time.perf_counter()
        client.post(f"{url}/services/error_recovery", json={}).raise_for_status()
        out.append((time.perf_counter() - started) * 1e3)
    return out


def line(what: str, ms: list[float]) -> str:
    return (
        f"{what}: p50 {percentile(ms, 0.5):.1f} ms, p99 {percentile(ms, 0.99):.1f} ms, max {max(ms):.1f} ms "
        f"({len(ms)} calls)"
    )


class Subscribers:
    """`clients` connections in one thread's event loop, each subscribed to TOPICS at throttle_rate 0."""

    def __init__(self, port: int, clients: int) -> None:
        self.port, self.clients, self.received = port, clients, 0
        self.ready = threading.Event()
        self.stop = threading.Event()
        self.thread = threading.Thread(target=lambda: asyncio.run(self._run()), daemon=True)

    async def _client(self, subscribed: list[int]) -> None:
        async with connect(f"ws://127.0.0.1:{self.port}/", max_size=None) as ws:
            for topic in TOPICS:
                await ws.send(json.dumps({"op": "subscribe", "topic": topic, "throttle_rate": 0}))
            subscribed.append(1)
            while not self.stop.is_set():
                try:
                    await asyncio.wait_for(ws.recv(), 0.5)
                except TimeoutError:
                    continue
                self.received += 1

    async def _run(self) -> None:
        subscribed: list[int] = []
        tasks = [asyncio.create_task(self._client(subscribed)) for _ in range(self.clients)]
        while len(subscribed) < self.clients:
            await asyncio.sleep(0.05)
        self.ready.set()
        await asyncio.gather(*tasks)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--clients", type=int, default=20)
    parser.add_argument("--calls", type=int, default=300)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    with running_server("--view", "none") as server, httpx.Client(timeout=120.0) as client:
        http_latencies(client, server.url, 20)  # warm-up
        alone = http_latencies(client, server.url, args.calls)
        subscribers = Subscribers(server.port, args.clients)
        subscribers.thread.start()
        subscribers.ready.wait(60)
        time.sleep(1.0)
        health0, count0, started = client.get(f"{server.url}/health").json(), subscribers.received, time.perf_counter()
        loaded = http_latencies(client, server.url, args.calls)
        rest = args.seconds - (time.perf_counter() - started)
        if rest > 0:
            time.sleep(rest)
        health1, count1, took = (
            client.get(f"{server.url}/health").json(),
            subscribers.received,
            time.perf_counter() - started,
        )
        subscribers.stop.set()
        subscribers.thread.join(10)
    ticks = health1["ticks"] - health0["ticks"]
    print(line("POST /services/error_recovery alone", alone))
    print(
        line(
            f"POST /services/error_recovery with {args.clients} clients x {len(TOPICS)} topics at throttle_rate 0",
            loaded,
        )
    )
    print(
        f"messages received by the clients: {(count1 - count0) / took:.0f}/s "
        f"(the lab's cap MAX_OUTGOING_RATE: {MAX_OUTGOING_RATE:g}/s)"
    )
    print(
        f"loop under the load: {ticks / took:.0f} ticks/s over {took:.1f} s, lateness p50 "
        f"{health1['lateness_p50_ms']:.2f} ms, p99 {health1['lateness_p99_ms']:.2f} ms, overruns "
        f"{health1['overruns'] - health0['overruns']}"
    )


if __name__ == "__main__":
    main()
