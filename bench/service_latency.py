"""Service latency over loopback at a steady request rate, measured by `wrk` (Debian package,
installed by `make bench`): `connections` connections, each waiting a random time, uniform in
[0, 2 connections/rate], before each request, so the offered load is `rate` requests per second
spread over time (a fixed wait would keep the connections in step: bursts of `connections`
requests at once); wrk reports the latency percentiles.
(A Python load generator cannot offer 500 req/s on these 2 cores without becoming the bottleneck.)

    .venv/bin/python -m bench.service_latency [--rate 500] [--seconds 10] [--repeats 3]
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import subprocess
import tempfile

import httpx

from app.serving.launch import running_server

SCRIPT = """
wrk.method = "POST"
wrk.body = '{"a": 20, "b": 22}'
wrk.headers["Content-Type"] = "application/json"
function init(args) math.randomseed(os.time()) end
function delay() return math.random(0, 2 * %d) end
"""


def to_ms(text: str) -> float:
    value, unit = re.fullmatch(r"([\d.]+)(us|ms|s)", text).groups()
    return float(value) * {"us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def run_wrk(url: str, rate: float, seconds: float, connections: int) -> dict:
    with tempfile.NamedTemporaryFile("w", suffix=".lua", delete=False) as script:
        script.write(SCRIPT % round(1000.0 * connections / rate))
    out = subprocess.run(
        [
            "wrk",
            "-t2",
            f"-c{connections}",
            f"-d{seconds:g}s",
            "-s",
            script.name,
            "--latency",
            f"{url}/services/add_two_ints",
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    percentiles = dict(re.findall(r"^\s+(\d+)%\s+(\S+)$", out, re.M))
    return {
        "p50": to_ms(percentiles["50"]),
        "p99": to_ms(percentiles["99"]),
        "rate": float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1)),
        "errors": "Non-2xx" in out or "Socket errors" in out,
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rate", type=float, default=500.0)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--connections", type=int, default=50)
    args = parser.parse_args()
    if shutil.which("wrk") is None:
        raise SystemExit("wrk is not installed: make bench installs it (apt-get install wrk)")
    with running_server("--view", "none") as server:
        runs = [run_wrk(server.url, args.rate, args.seconds, args.connections) for _ in range(args.repeats)]
        health = httpx.get(f"{server.url}/health").json()
    print(
        f"service latency, /add_two_ints over loopback, offered {args.rate:g} req/s ({args.repeats} x {args.seconds:g} s):"
    )
    for key in ("p50", "p99"):
        values = [r[key] for r in runs]
        print(
            f"  {key} median {statistics.median(values):.2f} ms (runs {', '.join(f'{v:.2f}' for v in values)})"
            + ("  target < 10 ms" if key == "p99" else "")
        )
    print(f"  achieved {statistics.median(r['rate'] for r in runs):.0f} req/s")
    print(
        f"  errors: {any(r['errors'] for r in runs)}; the 1 kHz loop meanwhile: {health['rate_hz']:.0f} ticks/s, "
        f"lateness p99 {health['lateness_p99_ms']:.2f} ms"
    )


if __name__ == "__main__":
    main()
