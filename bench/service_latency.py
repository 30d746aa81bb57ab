"""Service latency over loopback at a steady request rate (open loop: each request is sent at its
scheduled time, latency counts from that time, so a slow server cannot hide its queue).

    .venv/bin/python bench/service_latency.py [--rate 500] [--seconds 10] [--repeats 3]
"""
from __future__ import annotations

import argparse
import asyncio
import statistics
import time

import httpx

from app.launch import running_server


async def steady(url: str, rate: float, seconds: float) -> tuple[list[float], int]:
    latencies: list[float] = []
    errors = 0
    limits = httpx.Limits(max_connections=64, max_keepalive_connections=64)
    async with httpx.AsyncClient(base_url=url, limits=limits, timeout=httpx.Timeout(10.0, pool=30.0)) as client:
        start = time.perf_counter()

        async def one(k: int) -> None:
            nonlocal errors
            scheduled = start + k / rate
            await asyncio.sleep(max(0.0, scheduled - time.perf_counter()))
            try:
                r = await client.post("/services/add_two_ints", json={"a": k, "b": 1})
                errors += r.status_code != 200
            except httpx.HTTPError:
                errors += 1
            latencies.append(time.perf_counter() - scheduled)

        await asyncio.gather(*(one(k) for k in range(int(rate * seconds))))
    return latencies, errors


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rate", type=float, default=500.0)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with running_server("--view", "none") as server:
        runs = [asyncio.run(steady(server.url, args.rate, args.seconds)) for _ in range(args.repeats)]
        health = httpx.get(f"{server.url}/health").json()
    p50s = [pct(lat, 0.5) * 1e3 for lat, _ in runs]
    p99s = [pct(lat, 0.99) * 1e3 for lat, _ in runs]
    errors = sum(e for _, e in runs)
    print(f"service latency at {args.rate:g} req/s over loopback ({args.repeats} x {args.seconds:g} s, /add_two_ints):")
    print(f"  p50 median {statistics.median(p50s):.2f} ms (runs {', '.join(f'{x:.2f}' for x in p50s)})")
    print(f"  p99 median {statistics.median(p99s):.2f} ms (runs {', '.join(f'{x:.2f}' for x in p99s)})  target < 10 ms")
    print(f"  errors {errors}; loop meanwhile {health['rate_hz']:.0f} ticks/s, lateness p99 {health['lateness_p99_ms']:.2f} ms")


if __name__ == "__main__":
    main()
