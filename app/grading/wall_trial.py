"""One wall-following trial of a student's program (the grader's job: app/cli/grade_wall.py hands it to
sim/procedures/runner.py): the trial's mobile world served on a free loopback port (the lab, its
rosbridge endpoint), the program started as `hri-lab run` starts it (its own process and session,
in bubblewrap's jail; it reaches the world only through rosbridge: /scan in, /cmd_vel out), and the verdict read from the
world's monitor (sim/mobile/monitor.py), which the program cannot reach.

The trial's clock starts at the program's first /cmd_vel (its start-up is not timed); the
simulation runs in real time, as a Gazebo world does by default, so a trial takes up to the rules'
time limit of wall-clock time.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from collections import deque
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import uvicorn

from sim.controllers.sandbox.jail import CHILD_ENV, bwrap_command
from sim.mobile.world import MobileConfig

from app.grading.report import Item
from app.grading.wall import TrialOutcome, trial_item
from app.mobile.lab import MobileLab
from app.serving.compose import create_app
from app.serving.http import server_config
from app.serving.launch import free_port, stop_group

FIRST_COMMAND_S = 90.0  # s of wall clock for the program to start and publish its first /cmd_vel
BEHIND_S = 120.0  # s of wall clock beyond the time limit before a trial that falls behind is ended
POLL_S = 0.05
OUTPUT_LINES = 5  # the program's last lines quoted when it ended on its own


@contextmanager
def served(config: MobileConfig) -> Iterator[tuple[MobileLab, str]]:
    """The trial's world as `hri-lab serve --world mobile --view none` serves it, in this process."""
    lab = MobileLab(config)
    lab.graded = True  # the program reaches the lab's HTTP API too: it may not reset the trial's world
    port = free_port()
    server = uvicorn.Server(server_config(create_app(lab, view="none"), "127.0.0.1", port))
    thread = threading.Thread(target=server.run, name="wall-trial-server", daemon=True)
    thread.start()
    try:
        deadline = time.monotonic() + 120.0
        while not server.started:
            if not thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError("the trial's lab did not start")
            time.sleep(0.02)
        yield lab, f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(timeout=30.0)


PROGRAM_MEMORY_BYTES = 2 << 30  # RLIMIT_AS of a jailed program (Python, numpy, the rospy/rclpy layer)
PROGRAM_OPEN_FILES = 256  # RLIMIT_NOFILE: its sockets, pipes and files
# the packages `hri-lab run` imports (not their checkout; sim/ the jail shows to every child)
LAB_CODE = tuple(str(Path(__file__).resolve().parents[2] / top) for top in ("interfaces", "app", "rosclient"))


def _limits() -> None:
    """The jailed program's limits, set in the child before bubblewrap starts (inherited)."""
    resource.setrlimit(resource.RLIMIT_AS, (PROGRAM_MEMORY_BYTES, PROGRAM_MEMORY_BYTES))
    resource.setrlimit(resource.RLIMIT_NOFILE, (PROGRAM_OPEN_FILES, PROGRAM_OPEN_FILES))


class Program:
    """The student's program under `hri-lab run`, its output kept (the last lines). Jailed (the
    default) it runs in bubblewrap as a graded controller does (sim/controllers/sandbox/jail.py), with
    the host's network to reach its trial's lab: it sees the interpreter, the lab's packages and its own
    folder (a copy of its file alone) read-only, a private /tmp, no other process; its memory and descriptors are limited."""

    def __init__(self, url: str, path: Path, jailed: bool = True) -> None:
        self.lines: deque[str] = deque(maxlen=OUTPUT_LINES)
        command = [sys.executable, "-m", "app.cli", "run", "--url", url, str(path)]
        if jailed:
            folder = str(path.parent)
            command = bwrap_command(command, readable=(*LAB_CODE, folder), network=True, workdir=folder)
            env = dict(CHILD_ENV)
        else:
            env = {k: v for k, v in os.environ.items() if k not in ("HRI_LAB_URL", "HRI_LAB_TOKEN")}
        self.proc = subprocess.Popen(
            command,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            errors="replace",
            env=env,
            cwd=path.parent,
            start_new_session=True,  # its own group: stopped whole, with anything it started
            preexec_fn=_limits if jailed else None,
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None  # started with stdout=PIPE
        for line in self.proc.stdout:
            self.lines.append(line.rstrip()[:200])

    def stop(self) -> None:
        """Ctrl+C to its group, as a terminal sends it; killed if it is still there 5 s later."""
        stop_group(self.proc, 5.0)
        self._reader.join(timeout=5.0)

    def ended(self) -> str:
        code = self.proc.returncode
        tail = " | ".join(self.lines)
        return f"the program ended (exit status {code})" + (f"; its last lines: {tail}" if tail else "")


def judge(lab: MobileLab, program: Program, config: MobileConfig) -> TrialOutcome:
    """Wait for the monitor's verdict (or for the program's end, or its silence)."""
    started = time.monotonic()
    first_command = None
    while True:
        wall = lab.snapshot().wall
        if wall.done:
            return TrialOutcome(wall.passed, wall.verdict or "")
        now = time.monotonic()
        if wall.elapsed > 0.0 and first_command is None:
            first_command = now
        if program.proc.poll() is not None:
            when = f"at {wall.elapsed:.1f} s of the trial" if first_command else "before its first /cmd_vel"
            return TrialOutcome(False, f"program: {when} {program.ended()}")
        if first_command is None and now - started > FIRST_COMMAND_S:
            return TrialOutcome(False, f"program: no /cmd_vel within {FIRST_COMMAND_S:.0f} s of the program's start")
        if first_command is not None and now - first_command > config.rules.time_limit + BEHIND_S:
            return TrialOutcome(
                False, f"the simulation fell behind: {wall.elapsed:.1f} s simulated in {now - first_command:.0f} s"
            )
        time.sleep(POLL_S)


def run_trial(program_name: str, program_text: str, config: MobileConfig, index: int, jailed: bool = True) -> Item:
    """Trial `index` of the program (its file's name and text: a worker elsewhere has no copy);
    jailed unless the grader said --unsandboxed."""
    with tempfile.TemporaryDirectory(prefix="hri-lab-wall-") as folder:
        path = Path(folder) / Path(program_name).name
        path.write_text(program_text, encoding="utf-8")
        with served(config) as (lab, url):
            program = Program(url, path, jailed)
            try:
                outcome = judge(lab, program, config)
            finally:
                program.stop()
    return trial_item(index, config, outcome)
