"""A student's controller in a process of its own, under bubblewrap: the Controller protocol
(reset/step/start/stop) answered by a child process the student's code cannot climb out of.

The child (sim/controllers/sandbox_child.py) runs in `bwrap --unshare-all --cap-drop ALL`: no
network, no other process, a read-only view of only what Python needs (/usr, the interpreter,
the virtual environment, the `sim` package), a private /tmp; memory (RLIMIT_AS) and CPU-time
(RLIMIT_CPU) limits; normal scheduling (posix_spawn resets SCHED_FIFO before exec, so no student
thread ever runs at the loop's real-time priority). The student's file is sent as text.

Each step the parent sends only what the real robot gives a controller and reads back 6 numbers;
it never unpickles anything from the child. Messages: a header `<cI` (opcode, payload bytes),
then the payload:
    parent -> child  L load   filename NUL source (utf-8)
                     R reset  -
                     S step   float64[6 wrench_ee, 16 transform_ee_to_base (row-major), P params, dt]
                     A start  float64[P params, force]      O stop  float64[P params]
    child -> parent  k ok     step: float64[6 twist_base]; load: 2 bytes (has start, has stop)
                     p params float64[P params] + the service's message (utf-8)
                     e error  the reason, with the traceback (utf-8)
P = the fields of LiftingParams in declaration order (`running` as 0/1).

Faults (ControllerFault, the world turns it into an error state): an exception, a twist that is
not 6 finite numbers, no answer within `step_timeout` (a hang), the steps' wall time above
more than `max_sleeps` sleeps or blocking calls inside step() within `check_every` steps (its
voluntary context switches beyond the one read per step: a busy machine preempts, which is
involuntary, so load never counts against it), the CPU time (all threads) above `mean_cpu`,
a thread or process started, the process gone (os._exit, a signal, the memory or CPU limit).
After a fault the child is killed and every call fails with the same reason until reset()
(error_recovery), which lets the next call start a fresh child.

Parent and child take turns (one runs while the other waits), so the child is kept on the CPU the
parent runs on (re-checked every `check_every` steps): waking it on another CPU costs both
processes CPU time (bench/grade_time.py measures a step's CPU with the cores idle and busy).
"""
from __future__ import annotations

import ctypes
import dataclasses
import linecache
import math
import os
import select
import shutil
import signal
import struct
import subprocess
import sys
import time
import traceback
import types
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

import sim
from sim.controllers.interface import (
    ControllerFault,
    LiftingParams,
    start_lifting,
    stop_lifting,
)

HEADER = struct.Struct("<cI")
PARAM_FIELDS = tuple(f.name for f in dataclasses.fields(LiftingParams))
STEP_FLOATS = 6 + 16 + len(PARAM_FIELDS) + 1
STEP = struct.Struct(f"<cI{STEP_FLOATS}d")  # a whole step request, header included
TWIST = struct.Struct("<6d")
READ_CHUNK = 1 << 16  # bytes asked of a pipe per read (a whole answer arrives in one)
MAX_REPLY = 64 << 10  # bytes; a longer answer is a fault
MAX_TEXT = 4000  # characters of an error or message kept


@dataclass(frozen=True)
class SandboxBudget:
    """What a sandboxed controller may use (SI units)."""

    step_timeout: float = 10.0  # s wall for one answer: beyond it the child is hung (generous: a loaded machine stalls)
    load_timeout: float = 60.0  # s wall to start Python and import the file (a loaded machine is slow)
    max_sleeps: int = 10  # times step() may sleep or block (voluntary context switches) within `check_every` steps
    mean_cpu: float = 0.5e-3  # s per step, CPU of all the child's threads, over `window` steps
    window: int = 1000  # steps
    slow_step: float = 0.02  # s wall: a step this slow makes us look now
    check_every: int = 250  # steps between looks at the child's threads and CPU time (/proc)
    memory_bytes: int = 1 << 30  # RLIMIT_AS
    cpu_seconds: int = 0  # RLIMIT_CPU of one child (0 = none: the live server runs for hours)


def _params_to_floats(params: LiftingParams) -> list[float]:
    return [float(getattr(params, name)) for name in PARAM_FIELDS]


def _params_from_floats(values) -> LiftingParams:
    """LiftingParams from its fields' numbers (PARAM_FIELDS: the dataclass's order; `running` as 0/1)."""
    params = LiftingParams(*map(float, values))
    params.running = bool(params.running)
    return params


def _text(payload: bytes) -> str:
    return payload.decode("utf-8", errors="replace")[:MAX_TEXT]


# --- the sandbox's command line -----------------------------------------------------------------
def _readable_roots() -> list[str]:
    """What the child must see: the interpreter (venv and base), the `sim` package."""

    roots = {sys.prefix, sys.base_prefix, sys.exec_prefix, sys.base_exec_prefix, str(Path(sim.__file__).parent)}
    roots.add(str(Path(sys.executable).resolve().parent.parent))
    return sorted(r for r in roots if not r.startswith("/usr"))


def bwrap_command(child: list[str]) -> list[str]:
    bwrap = shutil.which("bwrap") or "bwrap"
    argv = [bwrap, "--unshare-all", "--die-with-parent", "--new-session", "--cap-drop", "ALL",
            "--ro-bind", "/usr", "/usr", "--tmpfs", "/tmp", "--proc", "/proc", "--dev", "/dev"]
    for top in ("/bin", "/sbin", "/lib", "/lib32", "/lib64"):
        if os.path.islink(top):
            argv += ["--symlink", os.readlink(top), top]
        elif os.path.isdir(top):
            argv += ["--ro-bind", top, top]
    for root in _readable_roots():
        argv += ["--ro-bind", root, root]
    return argv + ["--chdir", "/tmp", "--"] + child


def _child_command(budget: SandboxBudget, class_name: str) -> list[str]:
    return [sys.executable, "-m", "sim.controllers.sandbox_child", str(budget.memory_bytes), str(budget.cpu_seconds), class_name]


CHILD_ENV = {"PATH": "/usr/bin:/bin", "HOME": "/tmp", "LANG": "C.UTF-8", "PYTHONDONTWRITEBYTECODE": "1",
             "PYTHONHASHSEED": "0", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
             "NUMBA_NUM_THREADS": "1"}


@lru_cache(maxsize=None)
def sandbox_unavailable() -> str | None:
    """None when bubblewrap can run here, else why not (for `hri-lab grade`'s refusal)."""
    if shutil.which("bwrap") is None:
        return "bubblewrap (bwrap) is not installed: `apt-get install bubblewrap` (make test does it)"

    try:
        run = subprocess.run(bwrap_command(["/usr/bin/true"]), capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"bwrap cannot run: {exc}"
    return None if run.returncode == 0 else f"bwrap cannot run here: {run.stderr.strip() or run.returncode}"


_LIBC = ctypes.CDLL(None, use_errno=True)


def current_cpu() -> int | None:
    """The CPU the calling thread runs on now (glibc's sched_getcpu), None if unknown."""
    try:
        cpu = _LIBC.sched_getcpu()
    except AttributeError:
        return None
    return cpu if cpu >= 0 else None


# --- the parent's end ---------------------------------------------------------------------------
class SandboxedController:
    """The Controller protocol, answered by the student's class in a sandboxed child process."""

    def __init__(self, path: Path, class_name: str, budget: SandboxBudget = SandboxBudget(), sandboxed: bool = True) -> None:
        self.path, self.class_name, self.budget, self.sandboxed = Path(path), class_name, budget, sandboxed
        self.source = self.path.read_text(encoding="utf-8", errors="replace")
        self.name = class_name
        self.pid: int | None = None
        self._owner = 0  # the process that started the child (a fork must start its own)
        self.has_start = self.has_stop = False
        self._faulted = ""  # why the last child was stopped: every call fails fast until reset()
        self._switch_mark = self._switch_steps = 0  # the child's voluntary context switches, steps, at the last look
        self._steps = 0
        self._cpu_mark = (0, 0.0)  # (steps, child CPU s) at the start of the CPU window
        self._tasks = 0
        self._cpu: int | None = None  # the CPU the child is kept on (the parent's)

    # the Controller protocol
    def reset(self) -> None:
        self._faulted = ""  # error_recovery: the next call starts a fresh child
        if self._alive():
            self._call(b"R", b"", "reset")

    def step(self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
        request = STEP.pack(b"S", STEP.size - HEADER.size, *np.asarray(wrench_ee, float).ravel()[:6].tolist(),
                            *np.asarray(transform_ee_to_base, float).ravel()[:16].tolist(), *_params_to_floats(params),
                            float(dt))
        started = time.perf_counter()
        reply = self._call(b"S", request, "step")
        self._account(time.perf_counter() - started)
        if len(reply) != TWIST.size:
            self._fault(f"{self.name}.step returned {len(reply) // 8} numbers, expected 6 = [vx, vy, vz, wx, wy, wz]")
        twist = TWIST.unpack(reply)
        if not all(map(math.isfinite, twist)):
            self._fault(f"{self.name}.step returned a non-finite twist {list(twist)}")
        return np.array(twist)

    def start(self, params: LiftingParams, force: float) -> str:
        if not (self._faulted and not self.has_start):  # a stopped file without start() still has the lab's
            self._ensure()
        if not self.has_start:
            return start_lifting(params, force)
        return self._service(b"A", _params_to_floats(params) + [float(force)], params, "start")

    def stop(self, params: LiftingParams) -> str:
        if not (self._faulted and not self.has_stop):
            self._ensure()
        if not self.has_stop:
            return stop_lifting(params)
        return self._service(b"O", _params_to_floats(params), params, "stop")

    def close(self) -> None:
        """End the child (EOF, then SIGKILL if it lingers)."""
        pid, self.pid = self.pid, None
        for fd in (getattr(self, "_to_child", None), getattr(self, "_from_child", None)):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self._to_child = self._from_child = None
        if pid is not None and self._owner == os.getpid():
            _reap(pid, grace=0.5)

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass

    def __getstate__(self) -> dict:  # a copy in another process starts its own child
        state = dict(self.__dict__)
        state.update(pid=None, _to_child=None, _from_child=None, _owner=0)
        return state

    def load(self) -> "SandboxedController":
        """Start the child and import the file now (a file that cannot be loaded fails here)."""
        self._ensure()
        return self

    # the child's life
    def _alive(self) -> bool:
        return self.pid is not None and self._owner == os.getpid()

    def _ensure(self) -> None:
        if self._alive():
            return
        if self._faulted:  # no respawn at every step of the live loop: wait for reset (error_recovery)
            raise ControllerFault(self._faulted)
        self.pid = None  # a child of another process (fork) is not ours to talk to
        self._spawn()
        reply = self._call(b"L", str(self.path).encode() + b"\0" + self.source.encode(), "load", self.budget.load_timeout)
        self.has_start, self.has_stop = bool(reply[:1] == b"\1"), bool(reply[1:2] == b"\1")
        self._steps = 0
        self._switch_mark, self._switch_steps = self._voluntary_switches(), 0
        self._tasks = self._count_tasks()
        self._cpu_mark = (0, self._cpu_time())
        self._cpu = None
        self._follow_parent()

    def _spawn(self) -> None:
        child = _child_command(self.budget, self.class_name)
        argv = bwrap_command(child) if self.sandboxed else child
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        errors_r, errors_w = os.pipe()
        try:
            self.pid = os.posix_spawn(argv[0], argv, CHILD_ENV if self.sandboxed else {**os.environ, **CHILD_ENV}, file_actions=[
                (os.POSIX_SPAWN_OPEN, 0, os.devnull, os.O_RDONLY, 0),
                (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                (os.POSIX_SPAWN_DUP2, errors_w, 2),
                (os.POSIX_SPAWN_DUP2, to_child_r, 3),
                (os.POSIX_SPAWN_DUP2, from_child_w, 4),
            ], setsid=True, scheduler=(os.SCHED_OTHER, os.sched_param(0)))
        except OSError as exc:
            for fd in (to_child_r, to_child_w, from_child_r, from_child_w, errors_r, errors_w):
                os.close(fd)
            raise ControllerFault(f"cannot start the controller's process: {exc}") from None
        for fd in (to_child_r, from_child_w, errors_w):
            os.close(fd)
        self._owner = os.getpid()
        self._to_child, self._from_child, self._errors = to_child_w, from_child_r, errors_r
        self._inbox = b""  # bytes read from the child, not yet used
        os.set_blocking(errors_r, False)

    # one request, one answer
    def _call(self, op: bytes, payload: bytes, what: str, timeout: float | None = None) -> bytes:
        """One request (op and payload; a step's request comes packed with its header) and its answer."""
        if op != b"L":
            self._ensure()
        try:
            _write_all(self._to_child, payload if op == b"S" else HEADER.pack(op, len(payload)) + payload)
        except (BrokenPipeError, OSError):
            self._fault(f"{self.name}.{what}: {self._death()}")
        deadline = time.perf_counter() + (timeout or self.budget.step_timeout)
        header = self._read(HEADER.size, deadline, what)
        kind, size = HEADER.unpack(header)
        if size > MAX_REPLY:
            self._fault(f"{self.name}.{what} answered {size} bytes (at most {MAX_REPLY})")
        body = self._read(size, deadline, what)
        if kind == b"e":
            self._fault(_text(body) if what == "load" else f"{self.name}.{what} {_text(body)}")
        if kind not in (b"k", b"p"):
            self._fault(f"{self.name}.{what}: the controller's process answered nonsense")
        return body

    def _read(self, size: int, deadline: float, what: str) -> bytes:
        """`size` bytes of the answer (what the pipe holds is read at once and kept for the next call)."""
        while len(self._inbox) < size:
            left = deadline - time.perf_counter()
            ready = select.select([self._from_child], [], [], max(0.0, left))[0] if left > 0 else []
            if not ready:
                waited = self.budget.load_timeout if what == "load" else self.budget.step_timeout
                self._fault(f"{self.name}.{what} did not answer within {waited:g} s (wall clock): stopped")
            chunk = os.read(self._from_child, READ_CHUNK)
            if not chunk:
                self._fault(f"importing {self.path} failed: {self._death()}" if what == "load" else f"{self.name}.{what}: {self._death()}")
            self._inbox += chunk
        data, self._inbox = self._inbox[:size], self._inbox[size:]
        return data

    def _service(self, op: bytes, values: list[float], params: LiftingParams, what: str) -> str:
        reply = self._call(op, np.asarray(values, float).tobytes(), what)
        count = len(PARAM_FIELDS) * 8
        new = np.frombuffer(reply[:count], dtype=np.float64) if len(reply) >= count else np.array([np.nan])
        fields = dict(zip(PARAM_FIELDS, new.tolist()))
        f_n_min, f_n_band, running = fields.get("f_n_min", np.nan), fields.get("f_n_band", np.nan), fields.get("running", np.nan)
        if not (np.isfinite(f_n_min) and np.isfinite(f_n_band) and running in (0.0, 1.0) and f_n_min >= 0 and f_n_band >= 0):
            self._fault(f"{self.name}.{what} left f_n_min = {f_n_min}, f_n_band = {f_n_band}, running = {running}: "
                        "expected finite forces >= 0 and running True or False")
        # only what the services own changes; the other fields belong to the parameter server
        params.f_n_min, params.f_n_band, params.running = f_n_min, f_n_band, bool(running)
        return _text(reply[count:])

    # watching the child
    def _follow_parent(self) -> None:
        """Keep the child's processes on the CPU this process runs on (they take turns)."""
        cpu = current_cpu()
        if cpu is None or cpu == self._cpu:
            return
        for pid in self._tree():
            try:
                os.sched_setaffinity(pid, {cpu})
            except OSError:  # gone, or not allowed here: it runs where the scheduler puts it
                pass
        self._cpu = cpu

    def _account(self, wall: float) -> None:
        budget = self.budget
        self._steps += 1
        if self._steps % budget.check_every and wall < budget.slow_step:
            return
        self._follow_parent()
        tasks = self._count_tasks()
        if tasks > self._tasks:
            self._fault(f"{self.name} started a thread or a process ({tasks - self._tasks} more): a controller runs "
                        "in its one thread, each step returns the twist")
        # between two steps the child blocks once, reading the next request; any other voluntary
        # context switch is a sleep or blocking I/O inside step() (being preempted is involuntary)
        switches = self._voluntary_switches()
        extra = switches - self._switch_mark - (self._steps - self._switch_steps)
        if self._steps % budget.check_every == 0:
            self._switch_mark, self._switch_steps = switches, self._steps
        if extra > budget.max_sleeps:
            self._fault(f"{self.name}.step sleeps or blocks: {extra} times within {budget.check_every} steps "
                        f"(at most {budget.max_sleeps}; the loop runs at 1 kHz, a step must return, not wait); "
                        f"last step {wall * 1e3:.1f} ms")
        steps, cpu = self._cpu_mark
        if self._steps - steps >= budget.window:
            used = self._cpu_time() - cpu
            mean = used / (self._steps - steps)
            if mean > budget.mean_cpu:
                self._fault(f"{self.name}.step used {mean * 1e3:.2f} ms of CPU per step over {self._steps - steps} steps "
                            f"(budget {budget.mean_cpu * 1e3:g} ms)")
            self._cpu_mark = (self._steps, used + cpu)

    def _tree(self) -> list[int]:
        if self.pid is None:
            return []
        pids, queue = [], [self.pid]
        while queue:
            pid = queue.pop()
            pids.append(pid)
            try:
                for tid in os.listdir(f"/proc/{pid}/task"):
                    with open(f"/proc/{pid}/task/{tid}/children") as handle:
                        queue += [int(c) for c in handle.read().split()]
            except OSError:
                pass
        return pids

    def _summed(self, read) -> float:
        """read(pid) summed over the child's processes; one that ended meanwhile (its /proc entry
        gone or cut short) counts 0."""
        total = 0
        for pid in self._tree():
            try:
                total += read(pid)
            except (OSError, IndexError, ValueError):
                pass
        return total

    def _count_tasks(self) -> int:
        return self._summed(lambda pid: len(os.listdir(f"/proc/{pid}/task")))

    def _voluntary_switches(self) -> int:
        """The child's processes' voluntary context switches (/proc/PID/status)."""
        def switches(pid: int) -> int:
            with open(f"/proc/{pid}/status") as handle:
                return sum(int(line.split()[1]) for line in handle if line.startswith("voluntary_ctxt_switches"))

        return self._summed(switches)

    def _cpu_time(self) -> float:
        """s of CPU used by the child's processes (all threads): utime + stime from /proc."""
        def ticks(pid: int) -> int:
            with open(f"/proc/{pid}/stat") as handle:
                rest = handle.read().rpartition(")")[2].split()
            return int(rest[11]) + int(rest[12])

        return self._summed(ticks) / os.sysconf("SC_CLK_TCK")

    def _death(self) -> str:
        """Why the child is gone (its exit code or signal), with what it said on stderr."""
        status = _reap(self.pid, grace=1.0) if self._alive() else None
        said = ""
        try:
            said = _text(os.read(self._errors, MAX_TEXT)).strip()
        except (OSError, AttributeError, TypeError):
            pass
        if status is None:
            why = "the controller's process is gone"
        elif os.WIFSIGNALED(status):
            sig = os.WTERMSIG(status)
            hint = {signal.SIGXCPU: " (CPU-time limit)", signal.SIGKILL: " (killed: memory or time limit)",
                    signal.SIGSEGV: " (a crash)"}.get(sig, "")
            why = f"the controller's process was killed by {signal.Signals(sig).name}{hint}"
        else:
            why = f"the controller's process exited with code {os.WEXITSTATUS(status)} (os._exit or sys.exit)"
        return why + (f"; it said: {said}" if said else "")

    def _fault(self, reason: str):
        self.close()
        self._faulted = reason
        raise ControllerFault(reason)


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def _reap(pid: int, grace: float) -> int | None:
    """Wait up to `grace` s for the child to exit, then SIGKILL it; its wait status."""
    end = time.perf_counter() + grace
    while True:
        try:
            done, status = os.waitpid(pid, os.WNOHANG)
        except ChildProcessError:
            return None
        if done:
            return status
        if time.perf_counter() > end:
            try:
                os.killpg(pid, signal.SIGKILL)
            except OSError:
                pass
            try:
                return os.waitpid(pid, 0)[1]
            except ChildProcessError:
                return None
        time.sleep(0.005)


# --- the child's end (runs inside the sandbox) ------------------------------------------------------
class ChildEnd:
    """Serves one instance of the student's class over two pipes."""

    def __init__(self, read_fd: int, write_fd: int) -> None:
        self.read_fd, self.write_fd = read_fd, write_fd
        self._inbox = b""  # bytes read from the parent, not yet used

    def _receive(self) -> tuple[bytes, bytes] | None:
        header = self._exact(HEADER.size)
        if header is None:
            return None
        op, size = HEADER.unpack(header)
        return op, self._exact(size) or b""

    def _exact(self, size: int) -> bytes | None:
        """`size` bytes (a whole request usually arrives in one read); None at the end of input."""
        while len(self._inbox) < size:
            chunk = os.read(self.read_fd, READ_CHUNK)
            if not chunk:
                return None
            self._inbox += chunk
        data, self._inbox = self._inbox[:size], self._inbox[size:]
        return data

    def _send(self, kind: bytes, payload: bytes) -> None:
        _write_all(self.write_fd, HEADER.pack(kind, len(payload)) + payload)

    def _error(self, what: str, exc: BaseException) -> None:
        trace = "".join(traceback.format_exception(exc))
        self._send(b"e", f"raised {type(exc).__name__}: {exc}\n{trace}"[:MAX_TEXT].encode("utf-8", errors="replace"))

    def serve(self, class_name: str) -> int:
        message = self._receive()
        if message is None:
            return 0
        filename, _, source = message[1].partition(b"\0")
        try:
            instance = self._load(filename.decode(), source.decode("utf-8", errors="replace"), class_name)
        except BaseException as exc:  # noqa: BLE001 - even sys.exit() at import is a load error
            if isinstance(exc, LookupError):
                self._send(b"e", str(exc.args[0]).encode())
            else:
                self._send(b"e", f"importing {filename.decode()} failed: {type(exc).__name__}: {exc}".encode())
            return 1
        has = [callable(getattr(instance, name, None)) for name in ("start", "stop")]
        self._send(b"k", bytes(has))
        while (message := self._receive()) is not None:
            op, payload = message
            try:
                self._send(*self._handle(instance, op, payload))
            except BaseException as exc:  # noqa: BLE001 - reported; the parent decides
                self._error(op.decode(), exc)
        return 0

    @staticmethod
    def _load(filename: str, source: str, class_name: str):
        module = types.ModuleType("cooperative_lifting")
        module.__file__ = filename
        sys.modules[module.__name__] = module
        linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
        exec(compile(source, filename, "exec"), module.__dict__)  # noqa: S102 - the sandbox is the point
        cls = getattr(module, class_name, None)
        if not isinstance(cls, type):
            raise LookupError(f"{filename} has no class {class_name} (give another with {filename}:ClassName)")
        for method in ("reset", "step"):
            if not callable(getattr(cls, method, None)):
                raise LookupError(f"{class_name} in {filename} has no {method}() method")
        return cls()

    @staticmethod
    def _handle(instance, op: bytes, payload: bytes) -> tuple[bytes, bytes]:
        if op == b"R":
            instance.reset()
            return b"k", b""
        values = struct.unpack(f"<{len(payload) // 8}d", payload)
        if op == b"S":
            wrench, transform = np.array(values[:6]), np.array(values[6:22]).reshape(4, 4)
            params = _params_from_floats(values[22:-1])
            raw = instance.step(wrench, transform, params, values[-1])
            try:
                twist = np.asarray(raw, dtype=np.float64)
            except (TypeError, ValueError):
                raise TypeError(f"step returned {type(raw).__name__}, not 6 numbers") from None
            if twist.shape != (6,):
                raise ValueError(f"step returned shape {twist.shape}, expected (6,) = [vx, vy, vz, wx, wy, wz]")
            return b"k", twist.tobytes()
        params = _params_from_floats(values[:len(PARAM_FIELDS)])
        message = instance.start(params, float(values[-1])) if op == b"A" else instance.stop(params)
        return b"p", np.asarray(_params_to_floats(params), float).tobytes() + str(message)[:MAX_TEXT].encode("utf-8", "replace")
