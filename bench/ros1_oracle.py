"""ROS 1 programs run twice — under Debian's real ROS 1 (roscore, rospy 1.15: `make ros1`) and under
the lab's emulation (`hri-lab run`) — and what a user sees compared: the lines each program prints
(times, anonymous names' numbers and addresses masked), the graph it makes (its nodes, topics with
their types, services), parameter values and service answers. Every difference is printed; the
known ones, each with its reason, are listed in docs/ros-programs.md ("Checked against real ROS 1")
and in KNOWN below, which the test tier (tests/e2e/test_ros1_oracle.py) holds the run to.

    python -m bench.ros1_oracle            # every case; a line per difference, then the tally

The programs are the course's rospy programs (tests/ros_programs/). The interfaces they import that
Debian's packages lack (`example_interfaces`' AddTwoInts) are generated for real ROS with genpy, as
catkin's build does."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROGRAMS = ROOT / "tests" / "ros_programs"
INTERFACES = ROOT / "interfaces" / "share"
REAL_PYTHON = "/usr/bin/python3"  # Debian's, with python3-rospy
ROSCORE = "/usr/bin/roscore"
GENMSG = "/usr/lib/genpy/genmsg_py.py"
GENSRV = "/usr/lib/genpy/gensrv_py.py"
BOUND_S = 60.0  # s: a bound for a hung program (a loaded machine), never a measurement


def available() -> str | None:
    """None when real ROS 1 is installed, else what is missing (`make ros1` installs it)."""
    missing = [p for p in (REAL_PYTHON, ROSCORE, GENMSG, GENSRV) if not Path(p).exists()]
    if not missing and subprocess.run([REAL_PYTHON, "-c", "import rospy"], capture_output=True).returncode:
        missing.append("python3-rospy")
    return ", ".join(missing) or None


# --- what a user sees, made comparable ---------------------------------------------------------
MASKS = [
    (re.compile(r"\[(\d+\.\d+)\]"), "[T]"),  # rospy's log stamp: [INFO] [1733491234.567890]: ...
    (re.compile(r"(/[A-Za-z_]\w*?)_\d+_\d{10,}"), r"\1_N"),  # anonymous=True: name_<pid>_<time in ms>
    (re.compile(r"http://[^\s/]+:\d+/?"), "URI"),
]


def masked(line: str) -> str:
    for pattern, replacement in MASKS:
        line = pattern.sub(replacement, line)
    return line.rstrip()


@dataclass
class Step:
    """One program of a case: its file and arguments, the line it prints when it is ready for the
    next step (None: none needed), and how many lines of it are compared (None: all, it exits)."""

    program: str
    args: tuple[str, ...] = ()
    ready: str | None = None
    lines: int | None = None


@dataclass
class Case:
    name: str
    steps: list[Step]
    lab_declares: dict[str, object] = field(default_factory=dict)  # the lab's own parameters, set on ROS 1
    graph: bool = False  # compare the programs' part of the graph while the last step runs
    read_params: tuple[str, ...] = ()  # parameters read back after the programs ran


CASES = [
    Case("parameters", [Step("params_rospy.py")], lab_declares={"/cooperative_lifting/f_n_band": 5.0}),
    Case(
        "a latched talker and its listener: connection headers",
        [Step("snack_talker_rospy.py", lines=0), Step("snack_listener_rospy.py", lines=3)],
        graph=True,
    ),
    Case(
        "a service and its client (AddTwoInts)",
        [
            Step("add_two_ints_server_rospy.py", ready="Ready to add two ints."),
            Step("add_two_ints_client_rospy.py", ("3", "4")),
        ],
        graph=True,
    ),
    Case(
        "a publisher told of its peers (SubscribeListener)",
        [Step("subscribe_notify_rospy.py", ready="publishing", lines=1)],
        graph=True,
    ),
]

# Differences between the two that are kept, each with its reason (docs/ros-programs.md, "Checked
# against real ROS 1"): (case name or "*" for every case, text in the difference's line, reason).
KNOWN: list[tuple[str, str, str]] = []  # none left: rospy's logger services are advertised (issue 47)


# --- a side: where the programs run ----------------------------------------------------------
class Running:
    """A program started on one side, its output read line by line."""

    def __init__(self, argv: list[str], env: dict[str, str], cwd: Path) -> None:
        self.proc = subprocess.Popen(
            argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, cwd=cwd, start_new_session=True
        )
        self.lines: list[str] = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))

    def until(self, done: Callable[[], bool], what: str) -> None:
        end = time.monotonic() + BOUND_S
        while not done():
            if time.monotonic() > end or (self.proc.poll() is not None and not done()):
                self._reader.join(timeout=2)
                if done():
                    return
                raise RuntimeError(f"{what}: not within {BOUND_S:.0f} s; its output:\n" + "\n".join(self.lines))
            time.sleep(0.02)

    def stop(self) -> None:
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self._reader.join(timeout=5)


class Side:
    name = ""

    def start(self, step: Step) -> Running:
        raise NotImplementedError

    def set_param(self, name: str, value: object) -> None:
        raise NotImplementedError

    def get_param(self, name: str) -> object:
        raise NotImplementedError

    def graph(self) -> set[str]:
        """The graph as entries "node /n", "topic /t type", "service /s"."""
        raise NotImplementedError


class RealRos(Side):
    """roscore on a free port; programs under Debian's python3 with the generated interfaces."""

    name = "ROS 1"

    def __init__(self, home: Path, port: int) -> None:
        self.home, self.uri = home, f"http://127.0.0.1:{port}/"
        self.env = {
            "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
            "HOME": str(home),
            "ROS_HOME": str(home / "ros"),
            "ROS_LOG_DIR": str(home / "log"),
            "ROS_MASTER_URI": self.uri,
            "ROS_HOSTNAME": "127.0.0.1",
            "PYTHONPATH": str(home / "gen"),
            "PYTHONUNBUFFERED": "1",
        }
        generate_interfaces(home / "gen")
        self.core = Running([ROSCORE, "-p", str(port)], self.env, home)
        self.master = xmlrpc.client.ServerProxy(self.uri)
        end = time.monotonic() + BOUND_S
        while True:  # the master answers, and rosout has registered
            with contextlib.suppress(OSError, xmlrpc.client.Fault):
                code, _, state = self.master.getSystemState("/oracle")
                if code == 1 and any(topic == "/rosout" for topic, _ in state[1]):
                    break
            if time.monotonic() > end or self.core.proc.poll() is not None:
                raise RuntimeError("roscore did not start:\n" + "\n".join(self.core.lines))
            time.sleep(0.1)

    def start(self, step: Step) -> Running:
        return Running([REAL_PYTHON, str(PROGRAMS / step.program), *step.args], self.env, PROGRAMS)

    def set_param(self, name: str, value: object) -> None:
        self.master.setParam("/oracle", name, value)

    def get_param(self, name: str) -> object:
        code, message, value = self.master.getParam("/oracle", name)
        return value if code == 1 else f"<{message}>"

    def graph(self) -> set[str]:
        _, _, (publishers, subscribers, services) = self.master.getSystemState("/oracle")
        _, _, types = self.master.getTopicTypes("/oracle")
        typed = dict(types)
        entries = {f"topic {t} {typed.get(t, '?')}" for t, _ in publishers + subscribers}
        entries |= {f"node {n}" for _, nodes in publishers + subscribers + services for n in nodes}
        entries |= {f"service {s}" for s, _ in services}
        return entries

    def close(self) -> None:
        self.core.stop()


class Lab(Side):
    """A lab (`hri-lab serve`) and programs under `hri-lab run`; the graph from rosapi (roslibpy)."""

    name = "lab"

    def __init__(self, server) -> None:
        import roslibpy

        self.url = server.url
        self.env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        self.env.pop("HRI_LAB_URL", None)
        self.ros = roslibpy.Ros(
            "127.0.0.1", server.port, transport="asyncio"
        )  # as the tests' (one transport a process)
        self.ros.run(timeout=BOUND_S)

    def start(self, step: Step) -> Running:
        argv = [sys.executable, "-m", "app.cli", "run", "--url", self.url, str(PROGRAMS / step.program), *step.args]
        return Running(argv, self.env, ROOT)

    def _call(self, service: str, request: dict) -> dict:
        import roslibpy

        return dict(roslibpy.Service(self.ros, service, "").call(roslibpy.ServiceRequest(request), timeout=BOUND_S))

    def set_param(self, name: str, value: object) -> None:
        pass  # the lab declares these itself (Case.lab_declares)

    def get_param(self, name: str) -> object:
        value = self._call("/rosapi/get_param", {"name": name, "default": ""})["value"]
        return json.loads(value) if value else "<not set>"

    def graph(self) -> set[str]:
        topics = self._call("/rosapi/topics", {})
        entries = {f"topic {t} {ty}" for t, ty in zip(topics["topics"], topics["types"])}
        entries |= {f"node {n}" for n in self._call("/rosapi/nodes", {})["nodes"]}
        entries |= {f"service {s}" for s in self._call("/rosapi/services", {})["services"]}
        return entries

    def close(self) -> None:
        self.ros.terminate()


def generate_interfaces(out: Path) -> None:
    """The programs' own interface packages as catkin's build makes them: genpy's classes."""
    sources = {"example_interfaces": (INTERFACES / "example_interfaces", [], ["srv/AddTwoInts.srv"])}
    for package, (folder, msgs, srvs) in sources.items():
        for kind, files, script in (("msg", msgs, GENMSG), ("srv", srvs, GENSRV)):
            if not files:
                continue
            target = out / package / kind
            target.mkdir(parents=True, exist_ok=True)
            for name in files:
                subprocess.run(
                    [REAL_PYTHON, script, "-p", package, "-o", str(target), f"-I{package}:{folder / kind}"]
                    + [str(folder / name)],
                    check=True,
                    capture_output=True,
                )
            modules = sorted(p.stem for p in target.glob("_*.py"))
            (target / "__init__.py").write_text("".join(f"from .{m} import *\n" for m in modules))
        (out / package / "__init__.py").touch()


# --- a case run on a side, and the comparison -----------------------------------------------------
@dataclass
class Seen:
    lines: dict[str, list[str]]  # program -> its masked lines
    graph: set[str]
    params: dict[str, object]
    failure: str | None = None  # the step that never got where it should


def run_case(side: Side, case: Case) -> Seen:
    for name, value in case.lab_declares.items():
        side.set_param(name, value)
    running: list[tuple[Step, Running]] = []
    before = side.graph() if case.graph else set()
    failure = None
    try:
        for step in case.steps:
            program = side.start(step)
            running.append((step, program))
            if step.ready:
                program.until(
                    lambda p=program, t=step.ready: any(t in line for line in p.lines), f"{step.program} ready"
                )
        for step, program in running:
            if step.lines is not None:
                program.until(lambda p=program, n=step.lines: len(p.lines) >= n, f"{step.program}'s lines")
            elif not step.ready:
                program.until(lambda p=program: p.proc.poll() is not None, f"{step.program} to end")
        graph = {masked(entry) for entry in side.graph() - before} if case.graph else set()
    except RuntimeError as exc:  # a program that never got where it should: what it printed is compared
        failure, graph = str(exc).splitlines()[0], set()
    finally:
        for _, program in reversed(running):
            program.stop()
    lines = {
        step.program: [masked(line) for line in program.lines[: step.lines] if not line.startswith("Traceback")]
        for step, program in running
    }
    return Seen(lines, graph, {name: side.get_param(name) for name in case.read_params}, failure)


def differences(case: Case, real: Seen, lab: Seen) -> list[str]:
    found = [f"{who}: {seen.failure}" for who, seen in (("ROS 1", real), ("lab", lab)) if seen.failure]
    for program, real_lines in real.lines.items():
        lab_lines = lab.lines.get(program, [])
        if real_lines != lab_lines:
            found.append(f"{program} printed\n    ROS 1: {real_lines}\n    lab:   {lab_lines}")
    for entry in sorted(real.graph ^ lab.graph):
        found.append(f"graph: {entry!r} only under {'ROS 1' if entry in real.graph else 'the lab'}")
    for name in case.read_params:
        if real.params[name] != lab.params[name]:
            found.append(f"param {name}: ROS 1 {real.params[name]!r}, lab {lab.params[name]!r}")
    return [d for d in found if not any(k[0] in ("*", case.name) and k[1] in d for k in KNOWN)]


@contextlib.contextmanager
def sides() -> Iterator[tuple[RealRos, Lab]]:
    from app.serving.launch import free_port, running_server

    home = Path(tempfile.mkdtemp(prefix="ros1-oracle-"))
    real = None
    try:
        real = RealRos(home, free_port())
        with running_server("--view", "none", "--exercises") as server:  # the handouts' services are the programs'
            lab = Lab(server)
            try:
                yield real, lab
            finally:
                lab.close()
    finally:
        if real is not None:
            real.close()
        shutil.rmtree(home, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", action="append", help="only the cases whose name contains this")
    args = parser.parse_args()
    missing = available()
    if missing:
        sys.exit(f"real ROS 1 is not installed ({missing}): make ros1")
    cases = [c for c in CASES if not args.case or any(part in c.name for part in args.case)]
    with sides() as (real, lab):
        differing = 0
        for case in cases:
            found = differences(case, run_case(real, case), run_case(lab, case))
            differing += bool(found)
            print(f"{'same' if not found else 'DIFFERS'}: {case.name}", flush=True)
            for difference in found:
                print("  " + difference, flush=True)
    print(
        f"{len(cases) - differing} of {len(cases)} cases the same under ROS 1 and the lab ({len(KNOWN)} known differences)"
    )


if __name__ == "__main__":
    main()
