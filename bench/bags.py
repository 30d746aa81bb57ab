"""Bags' costs: recording the camera with the lab's topics, playing F_ext at 1 kHz to a program,
converting a minute's bag to ROS 1, and the resident memory of the commands on a decompression bomb.

    .venv/bin/python -m bench.bags [--record-seconds 20] [--play-seconds 10] [--convert-seconds 60]
                                   [--parts bomb,play,record,convert]

1. `hri-lab bag record -a` (every topic: /image_raw as fast as the camera renders, F_ext every
   step, the rest at rosbridge's pass-through) for `--record-seconds`: the recorder's CPU share
   (its CPU time / wall time, of one core), the server's (its process tree) beside it, images/s,
   MB/s written.
2. `hri-lab bag play` of a bag of F_ext at 1 kHz (stamped 1 ms apart) into `serve --replay`, to
   bench/ros_fext_subscriber.py under `hri-lab run`: the share of the messages that did not reach it.
3. `hri-lab bag convert` of a `--convert-seconds` recording of the lab's topics (no image): wall time.
4. The resident memory (maxrss) of `bag info`, `bag play` and `play` on tests/hostile_bags.py's bomb
   (one zstd chunk holding a 1.5 GB message, ~50 KB), and of `bag info` on a small honest bag.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx

from app.recording import bags
from app.serving.launch import ServerProcess
from tests import hostile_bags

ROOT = Path(__file__).parent.parent
HZ = os.sysconf("SC_CLK_TCK")


def tree_cpu_s(pid: int) -> float:
    """CPU seconds of a process and its children that are still alive (/proc)."""
    total = 0.0
    pids = [pid]
    while pids:
        p = pids.pop()
        try:
            fields = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()
            total += (int(fields[11]) + int(fields[12])) / HZ
            children = Path(f"/proc/{p}/task/{p}/children").read_text().split()
        except OSError:
            continue
        pids.extend(int(c) for c in children)
    return total


@contextmanager
def running_server(*args: str) -> Iterator[ServerProcess]:
    """A server with a start-up bound for a loaded machine (10 min)."""
    server = ServerProcess(*args, timeout=600.0)
    try:
        yield server
    finally:
        server.stop()


def cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "app.cli", *args]


def record_cost(seconds: float, folder: Path) -> None:
    with running_server("--view", "none") as server:
        httpx.get(f"{server.url}/camera/image.png", timeout=300)  # the camera process started and rendering
        time.sleep(3.0)
        server_before, wall = tree_cpu_s(server.proc.pid), time.monotonic()
        recorder = subprocess.Popen(
            cli(
                "bag",
                "record",
                "--url",
                server.url,
                "-a",
                "-O",
                str(folder / "all"),
                "--duration",
                str(seconds),
                "--max-mb",
                "8192",
            ),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            cwd=ROOT,
        )
        _, status, usage = os.wait4(recorder.pid, 0)
        recorder.returncode = os.waitstatus_to_exitcode(status)
        elapsed = time.monotonic() - wall
        server_share = (tree_cpu_s(server.proc.pid) - server_before) / elapsed
    info = bags.open_bag(folder / "all").info()
    counts = {t.name: t.count for t in info.topics}
    print(
        f"bag record -a, {seconds:g} s: recorder CPU {100 * (usage.ru_utime + usage.ru_stime) / elapsed:.0f}% of a core, "
        f"server (its processes) {100 * server_share:.0f}%; {info.size / elapsed / 1e6:.1f} MB/s written "
        f"({info.size / 1e6:.0f} MB); /image_raw {counts.get('/image_raw', 0) / elapsed:.1f} images/s, "
        f"F_ext {counts.get('/franka_state_controller/F_ext', 0) / elapsed:.0f}/s; {info.messages} messages"
    )


def fext_bag(path: Path, seconds: float) -> int:
    writer = bags.BagWriter(path, max_bytes=1 << 30)
    writer.add_topic("/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", None)
    n = int(seconds * 1000)
    for i in range(n):
        t = 1_000_000_000 + i * 1_000_000
        sec, nanosec = divmod(t, 1_000_000_000)
        writer.write(
            "/franka_state_controller/F_ext",
            t,
            {
                "header": {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": "panda_link8"},
                "wrench": {"force": {"x": 0.0, "y": 0.0, "z": 10.0 + i * 1e-3}, "torque": {}},
            },
        )
    writer.close()
    return n


def play_cost(seconds: float, folder: Path) -> None:
    n = fext_bag(folder / "fext", seconds)
    with running_server("--view", "none", "--replay") as server:
        listener = subprocess.Popen(
            cli("run", "--url", server.url, str(ROOT / "bench" / "ros_fext_subscriber.py"), str(seconds + 8)),
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
            cwd=ROOT,
        )
        time.sleep(4.0)  # the subscriber connected
        started = time.monotonic()
        player = subprocess.run(
            cli("bag", "play", "--url", server.url, str(folder / "fext")), capture_output=True, text=True
        )
        played_in = time.monotonic() - started
        out, _ = listener.communicate(timeout=120)
    result = json.loads(out.strip().splitlines()[-1])
    print(
        f"bag play of F_ext at 1 kHz ({n} messages, {seconds:g} s) to a rospy subscriber: {result['arrived']} arrived, "
        f"{100 * (1 - result['arrived'] / n):.1f}% dropped (played in {played_in:.1f} s; "
        f"{player.stderr.strip().splitlines()[-1]})"
    )


def convert_cost(seconds: float, folder: Path) -> None:
    with running_server("--view", "none") as server:
        time.sleep(3.0)
        subprocess.run(
            cli(
                "bag",
                "record",
                "--url",
                server.url,
                "-a",
                "-x",
                "/image_raw",
                "-O",
                str(folder / "minute"),
                "--duration",
                str(seconds),
            ),
            capture_output=True,
            check=True,
            cwd=ROOT,
        )
    info = bags.open_bag(folder / "minute").info()
    started = time.monotonic()
    count = bags.to_rosbag1(folder / "minute", folder / "minute.bag")
    elapsed = time.monotonic() - started
    print(
        f"bag convert of a {info.duration:.0f} s recording of the lab's topics ({info.messages} messages, "
        f"{info.size / 1e6:.1f} MB) to ROS 1: {elapsed:.1f} s ({count / elapsed:.0f} messages/s)"
    )


def maxrss_mib(*args: str) -> tuple[float, str]:
    done = subprocess.run([sys.executable, "-c", hostile_bags.MEASURE, *args], capture_output=True, text=True, cwd=ROOT)
    rss = int(done.stderr.split("maxrss_kib")[1].split()[0]) / 1024
    reason = next((line for line in done.stderr.splitlines() if line.startswith("error")), "")
    return rss, reason


def bomb_memory(folder: Path) -> None:
    bomb = hostile_bags.bomb(folder / "bomb.mcap")
    honest = folder / "honest"
    if not honest.exists():
        fext_bag(honest, 1.0)
    rss, _ = maxrss_mib("bag", "info", str(honest))
    print(f"bag info on an honest bag: maxrss {rss:.0f} MiB")
    for command in (("bag", "info"), ("bag", "play", "--url", "http://127.0.0.1:9"), ("play",)):
        rss, reason = maxrss_mib(*command, str(bomb))
        print(
            f"hri-lab {' '.join(command[:2])} on the bomb ({bomb.stat().st_size / 1024:.0f} KiB): maxrss {rss:.0f} MiB; {reason}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--record-seconds", type=float, default=20.0)
    parser.add_argument("--play-seconds", type=float, default=10.0)
    parser.add_argument("--convert-seconds", type=float, default=60.0)
    parser.add_argument("--parts", default="bomb,play,record,convert", help="which of the four to run")
    args = parser.parse_args()
    parts = args.parts.split(",")
    print(f"load average before: {os.getloadavg()[0]:.1f} (2 cores, shared)")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        if "bomb" in parts:
            bomb_memory(folder)
        if "play" in parts:
            play_cost(args.play_seconds, folder)
        if "record" in parts:
            record_cost(args.record_seconds, folder)
        if "convert" in parts:
            convert_cost(args.convert_seconds, folder)
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
