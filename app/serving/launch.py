"""Start `hri-lab serve` as a separate process on a free loopback port and wait until it is ready
(for tests, benchmarks and grading runs that need a real server)."""

import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager

KILL_WAIT_S = 10.0  # s to wait for a killed group's leader


def stop_group(proc: subprocess.Popen, grace_s: float) -> None:
    """Stop a program started in a process group of its own: Ctrl+C to the group, as a terminal sends
    it; SIGKILL if it is still there `grace_s` later; then SIGKILL to whatever it left in its group."""
    for sig, wait in ((signal.SIGINT, grace_s), (signal.SIGKILL, KILL_WAIT_S)):
        if proc.poll() is not None:
            break
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(timeout=wait)
        except subprocess.TimeoutExpired:
            continue
    try:  # what it left in its group (a child it started)
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def wait_or_kill(proc: subprocess.Popen, grace_s: float) -> None:
    """Waits for a process told to end; after `grace_s`, kills it and waits."""
    try:
        proc.wait(timeout=grace_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class ServerProcess:
    """`hri-lab serve ARGS` on a free port. Without --output-dir its recordings and figures go to a
    temporary folder that goes with it (never into the working tree)."""

    def __init__(self, *args: str, timeout: float = 120.0, own_session: bool = False) -> None:
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.started = time.perf_counter()
        self._output = None if "--output-dir" in args else tempfile.TemporaryDirectory(prefix="hri-lab-serve-")
        output = ("--output-dir", self._output.name) if self._output else ()
        self.proc = self._start(["serve", "--port", str(self.port), *output, *args], own_session)
        self.banner = self._wait_ready(timeout)
        self.ready_after = time.perf_counter() - self.started

    def _start(self, arguments: list[str], own_session: bool) -> subprocess.Popen:
        """`hri-lab ARGUMENTS` started, its output (stdout and stderr) read from `stdout`."""
        return subprocess.Popen(
            [sys.executable, "-m", "app.cli", *arguments],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=own_session,  # out of the terminal's Ctrl+C: its starter stops it (hri-lab launch)
        )

    def _wait_ready(self, timeout: float) -> str:
        lines: list[str] = []
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            assert self.proc.stdout is not None  # started with stdout=PIPE
            line = self.proc.stdout.readline()
            lines.append(line)
            if "Press Ctrl+C" in line:
                return "".join(lines)
            if self.proc.poll() is not None:
                break
        self.stop()
        raise RuntimeError("the server did not start:\n" + "".join(lines))

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            wait_or_kill(self.proc, 10.0)
        if self._output is not None:
            self._output.cleanup()


@contextmanager
def running_server(*args: str, started: type[ServerProcess] = ServerProcess) -> Iterator[ServerProcess]:
    """`started(*args)` until the block ends (`started`: how the lab is started, the command by default)."""
    server = started(*args)
    try:
        yield server
    finally:
        server.stop()
