"""roslibpy's own test suites (its `tests/ros2` and `tests/ros1`, unchanged) against the lab: issue
27's measure of "what ROS clients expect of a ROS system" (docs/ros-programs.md).

The suites connect to `127.0.0.1:9090` (hard-coded in them), so this starts `hri-lab serve --port
9090 --view none` (port 9090 must be free) with its output in a temporary folder, copies the two
folders of a roslibpy checkout into another one (so neither this repository's nor roslibpy's pytest
settings apply), runs each with the lab's pinned roslibpy and prints pytest's summary line of each.

    git clone https://github.com/gramaziokohler/roslibpy /tmp/roslibpy   # not part of this repository
    .venv/bin/python -m bench.roslibpy_suite /tmp/roslibpy [--python PY] [-- PYTEST ARGS]

`--python PY` runs the suites with another interpreter's roslibpy: the release the checkout's tests
were written for (e.g. a venv with `pip install roslibpy==1.8.1 pytest` for the 1.8.1 checkout,
whose ros1 `test_actionlib.py` imports `roslibpy.actionlib`, which 2.x moved to `roslibpy.ros1`).
"""

from __future__ import annotations

import argparse
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PORT = 9090  # the suites' own
SUITES = ("ros2", "ros1")
SUITE_TIMEOUT = 900.0  # s: a bound for a hung suite, not a speed figure


def wait_listening(proc: subprocess.Popen, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise SystemExit(f"hri-lab serve ended with status {proc.returncode} (is port {PORT} free?)")
        try:
            socket.create_connection(("127.0.0.1", PORT), timeout=1).close()
            return
        except OSError:
            time.sleep(0.2)
    raise SystemExit(f"hri-lab serve did not listen on {PORT} within {timeout:g} s")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("checkout", type=Path, help="a roslibpy checkout (its tests/ros2 and tests/ros1 are run)")
    parser.add_argument("pytest_args", nargs="*", help="more pytest arguments (after --)")
    parser.add_argument(
        "--python", default=sys.executable, help="the interpreter (with roslibpy and pytest) that runs the suites"
    )
    args = parser.parse_args()
    missing = [s for s in SUITES if not (args.checkout / "tests" / s).is_dir()]
    if missing:
        print(f"{args.checkout}: no tests/{', tests/'.join(missing)} (a roslibpy checkout?)", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory(prefix="roslibpy-suite-") as tmp:
        work = Path(tmp)
        for suite in SUITES:
            shutil.copytree(args.checkout / "tests" / suite, work / suite)
        server = subprocess.Popen(
            [sys.executable, "-m", "app.cli", "serve", "--port", str(PORT), "--view", "none", "--output-dir", tmp],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            cwd=tmp,
        )
        try:
            wait_listening(server)
            for suite in SUITES:
                extra = ["--continue-on-collection-errors"] if suite == "ros1" else []
                run = subprocess.run(
                    [args.python, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--rootdir", tmp, *extra]
                    + [*args.pytest_args, suite],
                    cwd=tmp,
                    capture_output=True,
                    text=True,
                    timeout=SUITE_TIMEOUT,
                )
                lines = [line for line in run.stdout.splitlines() if line.strip()]
                failed = [line for line in lines if line.startswith(("FAILED", "ERROR"))]
                print(f"tests/{suite}: {lines[-1].strip('= ') if lines else run.stderr.strip()}")
                for line in failed:
                    print(f"  {line}")
        finally:
            server.terminate()
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                server.kill()
                server.wait()
    return 0


if __name__ == "__main__":
    sys.exit(main())
