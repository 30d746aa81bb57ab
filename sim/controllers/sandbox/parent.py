"""SandboxedController: the Controller protocol (reset/step/start/stop) answered by the student's
class in a child process inside the jail (jail.py), over the wire (wire.py).

The child runs with normal scheduling (posix_spawn resets SCHED_FIFO before exec, so no student
thread ever runs at the loop's real-time priority). The student's file is sent as text.

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

import math
import os
import select
import time
from pathlib import Path

import numpy as np

from sim.controllers.interface import ControllerFault, LiftingParams, start_lifting, stop_lifting
from sim.controllers.sandbox import watch, wire
from sim.controllers.sandbox.budget import SandboxBudget
from sim.controllers.sandbox.jail import CHILD_ENV, bwrap_command, child_command


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
        request = wire.STEP.pack(b"S", wire.STEP.size - wire.HEADER.size, *np.asarray(wrench_ee, float).ravel()[:6].tolist(),
                                 *np.asarray(transform_ee_to_base, float).ravel()[:16].tolist(),
                                 *wire.params_to_floats(params), float(dt))
        started = time.perf_counter()
        reply = self._call(b"S", request, "step")
        self._account(time.perf_counter() - started)
        if len(reply) != wire.TWIST.size:
            self._fault(f"{self.name}.step returned {len(reply) // 8} numbers, expected 6 = [vx, vy, vz, wx, wy, wz]")
        twist = wire.TWIST.unpack(reply)
        if not all(map(math.isfinite, twist)):
            self._fault(f"{self.name}.step returned a non-finite twist {list(twist)}")
        return np.array(twist)

    def start(self, params: LiftingParams, force: float) -> str:
        if not (self._faulted and not self.has_start):  # a stopped file without start() still has the lab's
            self._ensure()
        if not self.has_start:
            return start_lifting(params, force)
        return self._service(b"A", wire.params_to_floats(params) + [float(force)], params, "start")

    def stop(self, params: LiftingParams) -> str:
        if not (self._faulted and not self.has_stop):
            self._ensure()
        if not self.has_stop:
            return stop_lifting(params)
        return self._service(b"O", wire.params_to_floats(params), params, "stop")

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
            watch.reap(pid, grace=0.5)

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

    def _tree(self) -> list[int]:
        return watch.process_tree(self.pid)

    def _cpu_time(self) -> float:
        """s of CPU used by the child's processes (all threads)."""
        return watch.cpu_time(self._tree())

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
        tree = self._tree()
        self._switch_mark, self._switch_steps = watch.voluntary_switches(tree), 0
        self._tasks = watch.count_tasks(tree)
        self._cpu_mark = (0, watch.cpu_time(tree))
        self._cpu = None
        self._follow_parent()

    def _spawn(self) -> None:
        child = child_command(self.budget, self.class_name)
        argv = bwrap_command(child) if self.sandboxed else child
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        errors_r, errors_w = os.pipe()
        try:
            self.pid = os.posix_spawn(argv[0], argv, CHILD_ENV if self.sandboxed else {**os.environ, **CHILD_ENV}, file_actions=[
                (os.POSIX_SPAWN_OPEN, 0, os.devnull, os.O_RDONLY, 0),
                (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                (os.POSIX_SPAWN_DUP2, errors_w, 2),
                (os.POSIX_SPAWN_DUP2, to_child_r, wire.REQUEST_FD),
                (os.POSIX_SPAWN_DUP2, from_child_w, wire.ANSWER_FD),
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
            wire.write_all(self._to_child, payload if op == b"S" else wire.HEADER.pack(op, len(payload)) + payload)
        except (BrokenPipeError, OSError):
            self._fault(f"{self.name}.{what}: {self._death()}")
        deadline = time.perf_counter() + (timeout or self.budget.step_timeout)
        header = self._read(wire.HEADER.size, deadline, what)
        kind, size = wire.HEADER.unpack(header)
        if size > wire.MAX_REPLY:
            self._fault(f"{self.name}.{what} answered {size} bytes (at most {wire.MAX_REPLY})")
        body = self._read(size, deadline, what)
        if kind == b"e":
            self._fault(wire.text(body) if what == "load" else f"{self.name}.{what} {wire.text(body)}")
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
            chunk = os.read(self._from_child, wire.READ_CHUNK)
            if not chunk:
                self._fault(f"importing {self.path} failed: {self._death()}" if what == "load" else f"{self.name}.{what}: {self._death()}")
            self._inbox += chunk
        data, self._inbox = self._inbox[:size], self._inbox[size:]
        return data

    def _service(self, op: bytes, values: list[float], params: LiftingParams, what: str) -> str:
        reply = self._call(op, np.asarray(values, float).tobytes(), what)
        count = len(wire.PARAM_FIELDS) * 8
        new = np.frombuffer(reply[:count], dtype=np.float64) if len(reply) >= count else np.array([np.nan])
        fields = dict(zip(wire.PARAM_FIELDS, new.tolist()))
        f_n_min, f_n_band, running = fields.get("f_n_min", np.nan), fields.get("f_n_band", np.nan), fields.get("running", np.nan)
        if not (np.isfinite(f_n_min) and np.isfinite(f_n_band) and running in (0.0, 1.0) and f_n_min >= 0 and f_n_band >= 0):
            self._fault(f"{self.name}.{what} left f_n_min = {f_n_min}, f_n_band = {f_n_band}, running = {running}: "
                        "expected finite forces >= 0 and running True or False")
        # only what the services own changes; the other fields belong to the parameter server
        params.f_n_min, params.f_n_band, params.running = f_n_min, f_n_band, bool(running)
        return wire.text(reply[count:])

    # watching the child
    def _follow_parent(self) -> None:
        """Keep the child's processes on the CPU this process runs on (they take turns)."""
        cpu = watch.current_cpu()
        if cpu is None or cpu == self._cpu:
            return
        watch.keep_on_cpu(self._tree(), cpu)
        self._cpu = cpu

    def _account(self, wall: float) -> None:
        budget = self.budget
        self._steps += 1
        if self._steps % budget.check_every and wall < budget.slow_step:
            return
        self._follow_parent()
        tree = self._tree()
        tasks = watch.count_tasks(tree)
        if tasks > self._tasks:
            self._fault(f"{self.name} started a thread or a process ({tasks - self._tasks} more): a controller runs "
                        "in its one thread, each step returns the twist")
        # between two steps the child blocks once, reading the next request; any other voluntary
        # context switch is a sleep or blocking I/O inside step() (being preempted is involuntary)
        switches = watch.voluntary_switches(tree)
        extra = switches - self._switch_mark - (self._steps - self._switch_steps)
        if self._steps % budget.check_every == 0:
            self._switch_mark, self._switch_steps = switches, self._steps
        if extra > budget.max_sleeps:
            self._fault(f"{self.name}.step sleeps or blocks: {extra} times within {budget.check_every} steps "
                        f"(at most {budget.max_sleeps}; the loop runs at 1 kHz, a step must return, not wait); "
                        f"last step {wall * 1e3:.1f} ms")
        steps, cpu = self._cpu_mark
        if self._steps - steps >= budget.window:
            used = watch.cpu_time(tree) - cpu
            mean = used / (self._steps - steps)
            if mean > budget.mean_cpu:
                self._fault(f"{self.name}.step used {mean * 1e3:.2f} ms of CPU per step over {self._steps - steps} steps "
                            f"(budget {budget.mean_cpu * 1e3:g} ms)")
            self._cpu_mark = (self._steps, used + cpu)

    def _death(self) -> str:
        """Why the child is gone (its exit code or signal), with what it said on stderr."""
        status = watch.reap(self.pid, grace=1.0) if self._alive() else None
        said = ""
        try:
            said = wire.text(os.read(self._errors, wire.MAX_TEXT)).strip()
        except (OSError, AttributeError, TypeError):
            pass
        return watch.why_ended(status) + (f"; it said: {said}" if said else "")

    def _fault(self, reason: str):
        self.close()
        self._faulted = reason
        raise ControllerFault(reason)
