"""One wall-following trial of a student's program (the grader's job: app/cli/grade_wall.py hands it to
sim/procedures/runner.py): the trial's mobile world served on a Unix socket of the trial's own (the
lab, its rosbridge endpoint; no port on the host's loopback), graded (its own admin token, which the
program never gets; the arena, the ground truth and the monitor hidden: app/mobile/world.py), the
program started as `hri-lab run` starts it (its own process and session, in bubblewrap's jail with a
network namespace of its own whose one way out is the lab's socket: app/cli/trial_link.py; one cgroup
for it and all it starts: sim/controllers/sandbox/cgroup.py; it reaches the world only through
rosbridge: /scan in, /cmd_vel out), and the verdict read from the world's monitor
(sim/mobile/monitor.py) in this process.

The trial's clock starts at the program's first /cmd_vel (its start-up is not timed); the
simulation runs in real time, as a Gazebo world does by default, so a trial takes up to the rules'
time limit of wall-clock time.
"""

from __future__ import annotations

import os
import resource
import secrets
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

from sim.controllers.sandbox.cgroup import MIB, GroupLimits, TrialGroup, cgroup_kind
from sim.controllers.sandbox.jail import CHILD_ENV, bwrap_command
from sim.mobile.world import MobileConfig, MobileSnapshot

from app.grading.report import Item
from app.grading.wall import TrialOutcome, trial_item
from app.serving.compose import create_app
from app.serving.http import server_config
from app.serving.launch import free_port, stop_group
from app.serving.worlds import WORLDS
from app.worlds.contract import LabOptions
from app.worlds.port import LabPort

FIRST_COMMAND_S = 90.0  # s of wall clock for the program to start and publish its first /cmd_vel
BEHIND_S = 120.0  # s of wall clock beyond the time limit before a trial that falls behind is ended
POLL_S = 0.05
OUTPUT_LINES = 5  # the program's last lines quoted when it ended on its own
DRAIN_S = 5.0  # s an ended program's output is read for at most (what it started may hold the pipe open)


WORLD = "mobile"  # the world its programs are graded in (app/serving/worlds.py)
LAB_SOCKET = "lab.sock"  # in the trial's folder, beside the program's copy
JAIL_PORT = 9090  # where the jailed program finds its lab: rosbridge's default port, in the jail's own namespace


@contextmanager
def served(config: MobileConfig, folder: Path) -> Iterator[tuple[LabPort[MobileSnapshot], Path]]:
    """The trial's world as `hri-lab serve --world mobile --view none` serves it, in this process, on
    the Unix socket folder/lab.sock, graded: changes need the trial's own token, which only this
    process holds (the program may publish, advertise and call its own nodes' services, as a node on
    a robot does; the lab's own services, driving and resetting from the API are refused to it)."""
    world = WORLDS[WORLD]
    lab = world.lab(LabOptions(config=config, graded=True))
    socket_path = folder / LAB_SOCKET
    app = create_app(world, lab, view="none", token=secrets.token_hex(16))
    server = uvicorn.Server(server_config(app, "127.0.0.1", 0, uds=str(socket_path)))
    thread = threading.Thread(target=server.run, name="wall-trial-server", daemon=True)
    thread.start()
    try:
        deadline = time.monotonic() + 120.0
        while not server.started:
            if not thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError("the trial's lab did not start")
            time.sleep(0.02)
        yield lab, socket_path
    finally:
        server.should_exit = True
        thread.join(timeout=30.0)


PROGRAM_MEMORY_BYTES = 2 << 30  # RLIMIT_AS of each jailed process (Python, numpy, the rospy/rclpy layer)
PROGRAM_OPEN_FILES = 256  # RLIMIT_NOFILE: its sockets, pipes and files
# the program and everything it starts, together (its cgroup): what one honest follower needs several times over
PROGRAM_LIMITS = GroupLimits(memory_bytes=1024 * MIB, pids=128, cpus=1.0)
LAB_GROWTH_BYTES = 512 * MIB  # the lab's growth in a trial (this process: its services, topics, messages)
# the packages `hri-lab run` imports (not their checkout; sim/ the jail shows to every child)
LAB_CODE = tuple(str(Path(__file__).resolve().parents[2] / top) for top in ("interfaces", "app", "rosclient"))


UNSANDBOXED = "none: run --unsandboxed (no jail, the grader's privileges, the host's network)"


def limits_of(group: TrialGroup | None, why: str) -> str:
    """What held a jailed program in a trial, in a report's words (the weaker limits named when no cgroup could be made)."""
    if group is not None:
        return group.statement()
    return (
        f"per process only (no cgroup: {why}): RLIMIT_AS {PROGRAM_MEMORY_BYTES / MIB:.0f} MiB and "
        f"RLIMIT_NOFILE {PROGRAM_OPEN_FILES} each, no cap on their sum, their count or their CPU"
    )


class Program:
    """The student's program under `hri-lab run`, its output kept (the last lines). Jailed (the
    default) it runs in bubblewrap as a graded controller does (sim/controllers/sandbox/jail.py), in a
    network namespace of its own whose one way out is its trial's lab (app/cli/trial_link.py): it
    sees the interpreter, the lab's packages and its own folder (a copy of its file alone, the lab's
    socket) read-only, a private /tmp, no other process; it and all it starts share one cgroup
    (PROGRAM_LIMITS: memory, processes, CPU), each process its RLIMIT_AS and descriptors."""

    def __init__(self, lab_socket: Path, path: Path, jailed: bool = True, name: str = "trial") -> None:
        self.lines: deque[str] = deque(maxlen=OUTPUT_LINES)
        self.group: TrialGroup | None = None
        port = JAIL_PORT if jailed else free_port()
        url = f"http://127.0.0.1:{port}"
        run = [sys.executable, "-m", "app.cli", "run", "--url", url, str(path)]
        command = [sys.executable, "-m", "app.cli.trial_link", str(lab_socket), str(port), "--", *run]
        why = ""
        if jailed:
            folder = str(path.parent)
            command = bwrap_command(command, readable=(*LAB_CODE, folder), workdir=folder)
            env = dict(CHILD_ENV)
            kind, why = cgroup_kind()
            if kind is not None:
                self.group = TrialGroup(f"{name}-{os.getpid()}-{secrets.token_hex(4)}", PROGRAM_LIMITS, kind)
        else:
            env = {k: v for k, v in os.environ.items() if k not in ("HRI_LAB_URL", "HRI_LAB_TOKEN")}
        self.limits = limits_of(self.group, why) if jailed else UNSANDBOXED
        group = self.group

        def limits() -> None:
            """In the child before bubblewrap starts (inherited by all it starts)."""
            if group is not None:
                group.join()
            resource.setrlimit(resource.RLIMIT_AS, (PROGRAM_MEMORY_BYTES, PROGRAM_MEMORY_BYTES))
            resource.setrlimit(resource.RLIMIT_NOFILE, (PROGRAM_OPEN_FILES, PROGRAM_OPEN_FILES))

        try:
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
                preexec_fn=limits if jailed else None,
            )
        except BaseException:
            if self.group is not None:
                self.group.close()
            raise
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None  # started with stdout=PIPE
        for line in self.proc.stdout:
            self.lines.append(line.rstrip()[:200])

    def stop(self) -> None:
        """Ctrl+C to its group, as a terminal sends it; killed if it is still there 5 s later; then
        whatever is left in its cgroup."""
        stop_group(self.proc, 5.0)
        if self.group is not None:
            self.group.close()
        self._reader.join(timeout=5.0)

    def ended(self) -> str:
        """Why it ended, with its last lines: read to their end first (on a loaded machine the reader's
        turn may come after the program has ended, and its last lines are the ones that say why)."""
        self._reader.join(timeout=DRAIN_S)
        code = self.proc.returncode
        hits = self.group.hit() if self.group is not None else []
        tail = " | ".join(self.lines)
        return (
            f"the program ended (exit status {code}"
            + "".join(f"; {h}" for h in hits)
            + ")"
            + (f"; its last lines: {tail}" if tail else "")
        )


def resident_bytes() -> int:
    """This process's resident memory (bytes): the trial's lab, served here."""
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def judge(lab: LabPort[MobileSnapshot], program: Program, config: MobileConfig) -> TrialOutcome:
    """Wait for the monitor's verdict (or for the program's end, or its silence, or the lab's
    memory grown beyond LAB_GROWTH_BYTES serving it: what the program makes the lab hold counts
    against it, its own cgroup aside)."""
    started = time.monotonic()
    first_command = None
    resident = resident_bytes()
    while True:
        grown = resident_bytes() - resident
        if grown > LAB_GROWTH_BYTES:
            return TrialOutcome(
                False,
                f"program: the lab's memory grew by {grown / MIB:.0f} MiB serving it (its cap: "
                f"{LAB_GROWTH_BYTES / MIB:.0f} MiB; what it advertised or sent the lab counts against it)",
            )
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


def run_trial(
    program_name: str, program_text: str, config: MobileConfig, index: int, seed: int, jailed: bool = True
) -> Item:
    """Trial `index` of the program (its file's name and text: a worker elsewhere has no copy), drawn
    from `seed`; jailed unless the grader said --unsandboxed. The item says what limits held the program."""
    with tempfile.TemporaryDirectory(prefix="hri-lab-wall-") as folder:
        path = Path(folder) / Path(program_name).name
        path.write_text(program_text, encoding="utf-8")
        with served(config, Path(folder)) as (lab, lab_socket):
            program = Program(lab_socket, path, jailed, name=f"trial{index}")
            try:
                outcome = judge(lab, program, config)
            finally:
                program.stop()
    item = trial_item(index, config, seed, outcome)
    item.detail += f" [limits: {program.limits}]"
    return item
