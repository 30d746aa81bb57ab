"""`hri-lab launch x.launch.py` and `hri-lab launch x.launch.yaml`: ROS 2's Python and YAML launch
files, as `ros2 launch` runs them.

A Python file's generate_launch_description() is called with the `launch`, `launch_ros` and
`ament_index_python` of rosclient/site on sys.path (this process only); the description is
performed by `Runner` here: entities visited in order (an action's condition first), processes
started (a Node as `hri-lab run PKG EXE --ros-args ...` runs it, an ExecuteProcess as its command,
`ros2 ...`/`rosrun ...` given to hri-lab's), timers, event handlers (a process started or exited,
the shutdown), EmitEvent(Shutdown). The launch ends when every process has ended and no timer is
pending, on a Shutdown event, or on Ctrl+C; it stops what still runs (SIGINT, then SIGTERM after
the action's sigterm_timeout, then SIGKILL) and runs the OnShutdown handlers first, as launch does.
A YAML file is read as its XML twin (rosclient/launch.py) and an XML file included from a Python
one too. Output is ros2 launch's: `[INFO] [talker-1]: process started with pid [...]`, a node's
lines prefixed `[talker-1] ` when its output is 'screen' or 'both' (every line goes to its log).
"""

from __future__ import annotations

import heapq
import itertools
import os
import queue
import runpy
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rosclient import boot, executables
from rosclient import launch as xml_launch
from rosclient.run import command, executable_command, program_env

_SITE = str(boot.SITE)
if _SITE not in sys.path:  # the launch vocabulary (site/launch, site/launch_ros) for this process
    sys.path.insert(0, _SITE)

from launch._core import LaunchDescriptionEntity  # noqa: E402 - importable once site/ is on sys.path

KILL_AFTER = 5.0  # s after SIGTERM before SIGKILL
COMMANDS = {"ros2": None, "rosrun": "run", "roslaunch": "launch", "rostopic": "topic", "rosservice": "service"}


class Process:
    """A started process: its output relayed and logged, its end noticed by the runner's loop."""

    def __init__(self, plan: Any, argv: list[str], env: dict[str, str], logs: Path) -> None:
        self.plan, self.argv = plan, argv
        self.log = logs / f"{plan.label}.log"
        self.proc = subprocess.Popen(
            argv,
            env=env,
            cwd=plan.cwd,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
            shell=plan.shell,
        )
        self.pid = self.proc.pid
        self.stopping_since: float | None = None
        self.termed = False
        self.reader = threading.Thread(target=self._relay, daemon=True)
        self.reader.start()

    def _relay(self) -> None:
        xml_launch.relay_output(
            self.proc, self.log, self.plan.label if self.plan.output in ("screen", "both") else None
        )


class Runner:
    """Performs a launch description (see the module's docstring). `dry`: processes are planned
    (`self.plans`), not started: a description's evaluation alone."""

    def __init__(
        self, url: str = "", logs: Path | None = None, dry: bool = False, workspace: str | None = None
    ) -> None:
        """`logs`: the folder of the processes' logs; by default made where ROS 2's launch makes it
        (xml_launch.log_dir), once a process or a file (a node's parameters) needs it."""
        from launch import LaunchContext

        self.url, self.dry, self.workspace = url, dry, workspace
        self._logs = logs
        self.context = LaunchContext(runner=self)
        self.plans: list[Any] = []
        self.processes: list[Process] = []
        self.handlers: list[Any] = []
        self.events: queue.Queue = queue.Queue()
        self.timers: list[tuple[float, int, list[Any], Any]] = []
        self._order = itertools.count()
        self._labels: dict[str, int] = {}
        self.died = 0
        self.shutting_down = False
        self.lines: list[str] = []  # what log() printed (a test reads it)

    @property
    def logs(self) -> Path:
        if self._logs is None:
            self._logs = xml_launch.log_dir()
        return self._logs

    # --- what the launch vocabulary asks of it --------------------------------------------------------

    def log(self, level: str, who: str, message: str) -> None:
        line = f"[{level}] [{who}]: {message}"
        self.lines.append(line)
        print(line, flush=True)

    def roots(self) -> list[Path]:
        return executables.workspaces(Path.cwd(), self.workspace)

    def package_dir(self, package: str) -> Path:
        from launch import SubstitutionFailure

        found = executables.find_package(package, self.roots())
        if found is None:
            raise SubstitutionFailure(f'package "{package}" not found (workspaces searched: {self.roots()})')
        return found[0]

    def executable(self, package: str, name: str) -> executables.Executable:
        from launch._core import LaunchError

        try:
            return executables.resolve(package, name, self.roots())
        except executables.NotFound as exc:
            raise LaunchError(str(exc)) from None

    def installed(self, found: executables.Executable) -> Path:
        """The file `ExecutableInPackage` names: what colcon/catkin install as lib/PKG/EXE, a script
        that runs the executable as `hri-lab run PKG EXE` does (its entry point called, or its script
        run with the lab's client libraries), with the arguments it is given. ExecuteProcess starts
        it as a command, as ROS's launch does."""
        argv = executable_command(found, [])
        script = self.logs / "lib" / found.package / found.name  # lib/PKG/EXE: its label is EXE, as in ROS
        text = (
            f"#!{sys.executable}\n"
            f"# {found.package}'s {found.name}, as the workspace would install it (made by the launch)\n"
            "import os, sys\n"
            f"argv = {argv!r} + sys.argv[1:]\n"
            "os.execv(argv[0], argv)\n"
        )
        if script.is_file() and script.read_text(encoding="utf-8") == text:
            return script  # installed once: a process started from it may be reading it now
        script.parent.mkdir(parents=True, exist_ok=True)
        made = self.temp_file(f"lib-{found.name}", "", text)
        made.chmod(0o755)
        os.replace(made, script)  # whole or not at all: a process never reads it half written
        return script

    def temp_file(self, prefix: str, suffix: str, text: str) -> Path:
        handle, name = tempfile.mkstemp(prefix=prefix + "-", suffix=suffix, dir=self.logs)
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            stream.write(text)
        return Path(name)

    def load(self, path: Path, kind: str, context: Any) -> Any:
        """The description of a launch file: a Python file's generate_launch_description(), an
        XML or YAML file's nodes and parameters (read by rosclient/launch.py)."""
        from launch import InvalidLaunchFileError, LaunchDescription

        if kind == "python" or (kind == "any" and path.suffix == ".py"):
            try:
                names = runpy.run_path(str(path), run_name="__launch__")
            except SyntaxError as exc:
                raise InvalidLaunchFileError(f"{path}: not Python ({exc})") from None
            generate = names.get("generate_launch_description")
            if not callable(generate):
                raise InvalidLaunchFileError(f"{path}: no generate_launch_description() function")
            described = generate()
            if not isinstance(described, LaunchDescription):
                raise InvalidLaunchFileError(f"{path}: generate_launch_description() returned no LaunchDescription")
            return described
        args = {k: v for k, v in context.launch_configurations.items() if isinstance(v, str)}
        try:
            read = xml_launch.read_yaml(path, args) if path.suffix in (".yaml", ".yml") else xml_launch.read(path, args)
        except xml_launch.LaunchError as exc:
            raise InvalidLaunchFileError(str(exc)) from None
        return LaunchDescription([_Nodes(read)])

    def start(self, plan: Any, context: Any) -> None:
        count = self._labels[plan.label] = self._labels.get(plan.label, 0) + 1
        plan.label = f"{plan.label}-{count}"
        self.plans.append(plan)
        if self.dry:
            return
        env = {**plan.env, **program_env(self.url, str(plan.workspace) if plan.workspace else self.workspace)}
        root = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, plan.env.get("PYTHONPATH", "")) if p)
        if plan.program is not None:
            argv = command(str(plan.program), plan.args, plan.entry)
        else:
            argv = self._command(plan.argv)
        process = Process(plan, argv, env, self.logs)
        self.processes.append(process)
        self.log("INFO", plan.label, f"process started with pid [{process.pid}]")
        from launch.events.process import ProcessStarted

        self.emit(
            ProcessStarted(action=plan.action, name=plan.label, cmd=argv, cwd=plan.cwd, env=None, pid=process.pid)
        )

    def _command(self, argv: list[str]) -> list[str]:
        if not argv or argv[0] not in COMMANDS:
            return argv
        lab = [sys.executable, "-m", "app.cli"]
        sub = COMMANDS[argv[0]]
        rest = argv[1:] if sub is None else [sub, *argv[1:]]
        if rest and rest[0] == "launch":
            rest = ["launch", "--url", self.url, *rest[1:]]
        return [*lab, *rest]

    def later(self, period: float, actions: list[Any], snapshot: Any, timer: Any) -> None:
        heapq.heappush(self.timers, (time.monotonic() + period, next(self._order), actions, (snapshot, timer)))

    def register(self, handler: Any) -> None:
        self.handlers.append(handler)

    def unregister(self, handler: Any) -> None:
        if handler in self.handlers:
            self.handlers.remove(handler)

    def emit(self, event: Any) -> None:
        self.events.put(event)

    # --- performing ------------------------------------------------------------------------------------
    def visit(self, entities: list[Any]) -> None:
        """Each entity, depth first, in order: what it returns is visited before the next one."""
        pending = list(reversed(entities))
        while pending:
            entity = pending.pop()
            if entity is None:
                continue
            more = entity.visit(self.context)
            if more:
                pending.extend(reversed(list(more)))

    def handle(self, event: Any) -> None:
        from launch.events import Shutdown

        for handler in list(self.handlers):
            if handler.matches(event):
                if handler.handle_once:
                    self.unregister(handler)
                saved = self.context.snapshot()
                self.visit(handler.handle(event, self.context))
                self.context.restore(saved)
        if isinstance(event, Shutdown) and not self.shutting_down:
            self.shutting_down = True
            self.timers.clear()
            for process in self.processes:
                if process.proc.poll() is None:
                    process.proc.send_signal(signal.SIGINT)
                    process.stopping_since = time.monotonic()

    def step(self) -> None:
        while True:
            try:
                event = self.events.get_nowait()
            except queue.Empty:
                break
            self.handle(event)
        now = time.monotonic()
        while self.timers and self.timers[0][0] <= now:
            _, _, actions, (snapshot, timer) = heapq.heappop(self.timers)
            if getattr(timer, "canceled", False):
                continue
            saved = self.context.snapshot()
            self.context.restore(snapshot)
            self.visit(actions)
            self.context.restore(saved)
        for process in self.processes:
            self._watch(process, now)

    def _watch(self, process: Process, now: float) -> None:
        code = process.proc.poll()
        if code is None:
            if process.stopping_since is not None:
                waited = now - process.stopping_since
                if not process.termed and waited > process.plan.sigterm_timeout:
                    process.termed = True
                    process.proc.terminate()
                elif waited > process.plan.sigterm_timeout + KILL_AFTER:
                    process.proc.kill()
            return
        if getattr(process, "ended", False):
            return
        process.ended = True  # type: ignore[attr-defined]
        process.reader.join(timeout=5)
        if code == 0 or (process.stopping_since is not None and code in (-signal.SIGINT, -signal.SIGTERM, 130, 143)):
            self.log("INFO", process.plan.label, f"process has finished cleanly [pid {process.pid}]")
        else:
            self.died += 1
            self.log(
                "ERROR",
                process.plan.label,
                f"process has died [pid {process.pid}, exit code {code}, cmd '{' '.join(process.argv)}'].",
            )
        from launch.events.process import ProcessExited

        self.emit(
            ProcessExited(
                action=process.plan.action,
                name=process.plan.label,
                cmd=process.argv,
                cwd=process.plan.cwd,
                env=None,
                pid=process.pid,
                returncode=code,
            )
        )
        if process.plan.respawn and not self.shutting_down:
            self.later(process.plan.respawn_delay, [_Respawn(process.plan)], self.context.snapshot(), None)

    def idle(self) -> bool:
        running = any(not getattr(p, "ended", False) for p in self.processes)
        return not running and not self.timers and self.events.empty()

    def run(self, path: Path, arguments: dict[str, str], stopping: threading.Event) -> int:
        from launch import LaunchDescription
        from launch.actions import IncludeLaunchDescription
        from launch.events import Shutdown

        self.context.launch_configurations.update(arguments)
        self.log("INFO", "launch", f"All log files can be found below {self.logs}")
        self.log("INFO", "launch", "Default logging verbosity is set to INFO")
        try:
            self.visit([LaunchDescription([IncludeLaunchDescription(str(path.resolve()))])])
        except BaseException:
            self.emit(Shutdown(reason="error"))
            raise
        shutdown_sent = False
        while True:
            self.step()
            if stopping.is_set() and not shutdown_sent:
                shutdown_sent = True
                self.log("WARNING", "launch", "user interrupted with ctrl-c (SIGINT)")
                self.emit(Shutdown(reason="ctrl-c (SIGINT)", due_to_sigint=True))
                continue
            if self.idle():
                if not self.shutting_down:
                    self.emit(Shutdown(reason="idle"))
                    self.step()
                if self.idle():
                    break
            time.sleep(0.05)
        return 1 if self.died else 0


class _Nodes(LaunchDescriptionEntity):
    """An XML or YAML launch file's nodes and parameters, started as its own launcher starts them."""

    def __init__(self, read: xml_launch.Launch) -> None:
        self.read = read

    def visit(self, context: Any) -> None:
        from launch._core import ProcessPlan

        runner = context.runner
        if self.read.params and not runner.dry:
            xml_launch.set_params(runner.url, self.read.params)
        for spec in self.read.nodes:
            plan = ProcessPlan(
                self,
                spec.name,
                program=spec.program,
                args=spec.argv(),
                output=spec.output,
                env=dict(context.environment),
            )
            runner.start(plan, context)


class _Respawn(LaunchDescriptionEntity):
    def __init__(self, plan: Any) -> None:
        self.plan = plan

    def visit(self, context: Any) -> None:
        plan = self.plan
        plan.label = plan.label.rsplit("-", 1)[0]
        context.runner.start(plan, context)


def run(path: Path, arguments: dict[str, str], url: str, workspace: str | None, stopping: threading.Event) -> int:
    """`hri-lab launch FILE.launch.py|.yaml` against the lab at url: the exit status."""
    runner = Runner(url, workspace=workspace)  # site/ on sys.path from here
    from launch._core import LaunchError
    from launch._core import Unsupported as Refused

    try:
        return runner.run(path, arguments, stopping)
    except (LaunchError, Refused) as exc:
        runner.log("ERROR", "launch", f"Caught exception in launch (see debug for traceback): {exc}")
        return 1
    finally:
        _stop_all(runner.processes)


def _stop_all(processes: list[Process]) -> None:
    alive = [p for p in processes if p.proc.poll() is None]
    for p in alive:
        p.proc.send_signal(signal.SIGINT)
    deadline = time.monotonic() + xml_launch.GRACE
    for p in alive:
        try:
            p.proc.wait(timeout=max(deadline - time.monotonic(), 0.1))
        except subprocess.TimeoutExpired:
            p.proc.kill()
            p.proc.wait()


def evaluate(path: Path, arguments: dict[str, str] | None = None, workspace: str | None = None) -> Runner:
    """A launch file's description performed without starting anything: `runner.plans` are the
    processes it would start first (timers and event handlers not run)."""
    from launch import LaunchDescription
    from launch.actions import IncludeLaunchDescription

    runner = Runner(dry=True, workspace=workspace)
    runner.context.launch_configurations.update(arguments or {})
    runner.visit([LaunchDescription([IncludeLaunchDescription(str(path.resolve()))])])
    return runner


def run_file(
    path: Path, arguments: dict[str, str], url: str | None, workspace: str | None, start_lab: Callable[[], Any] | None
) -> int:
    """`hri-lab launch x.launch.py`: `run` against the lab at `url`, or against one that `start_lab`
    starts (stopped after the launch, as the XML runner does: rosclient/launch.py's `lab_to_use`)."""
    stopping = xml_launch.stopped_by_signals()
    found = xml_launch.lab_to_use(url, start_lab)
    if found is None:
        return 2
    lab_url, server = found
    try:
        return run(path, arguments, lab_url, workspace, stopping)
    finally:
        if server is not None:
            server.stop()
