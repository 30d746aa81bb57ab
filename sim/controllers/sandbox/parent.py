"""SandboxedController: the Controller protocol (reset/step/start/stop) answered by the student's
class in a child process inside the jail (jail.py), through the wire (wire.py): a step's inputs
are written into the shared slot, one byte wakes the child, one byte wakes us when its twist is there.

The child is forked by its file's zygote (pool.py, zygote.py), which runs with normal scheduling
(posix_spawn resets SCHED_FIFO before exec, so no student thread ever runs at the loop's real-time
priority); it gets its own slot and pipes. The student's file is sent as text.

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

import fcntl
import math
import os
import select
import threading
import time
from pathlib import Path

import numpy as np

from sim.controllers.interface import ControllerFault, LiftingParams, lifting_refusal, start_lifting, stop_lifting
from sim.controllers.sandbox import pool, watch, wire
from sim.controllers.sandbox.budget import SandboxBudget

SHARED_WINDOW = 1.0  # s between two looks at what else the pinned pair's CPU does
SHARED_SHARE = 0.25  # of that time: a pair whose CPU did others' work longer is let go (_follow_parent)

_HANDLES = ("_to_child", "_from_child", "_errors")  # our ends of the child's pipes (descriptors)
_SLEPT: dict[tuple[str, str], float] = {}  # (file, class) -> s its items' steps slept here (SandboxBudget.file_sleep)


class SandboxedController:
    """The Controller protocol, answered by the student's class in a sandboxed child process."""

    # the live child's handles: set when it starts (_spawn), removed when it ends (close)
    _slot: wire.Slot
    _poll: select.poll
    _to_child: int
    _from_child: int
    _errors: int
    _seq: int
    _load_request: bytes

    def __init__(
        self, path: Path, class_name: str, budget: SandboxBudget = SandboxBudget(), sandboxed: bool = True
    ) -> None:
        self.path, self.class_name, self.budget, self.sandboxed = Path(path), class_name, budget, sandboxed
        self.source = self.path.read_text(encoding="utf-8", errors="replace")
        self.name = class_name
        self.pid: int | None = None
        self._owner = 0  # the process that started the child (a fork must start its own)
        self.has_start = self.has_stop = False
        self.stand_in = True  # a file without start()/stop() gets the lab's (the live lab); False: none (a grade)
        self._faulted = ""  # why the last child was stopped: every call fails fast until reset()
        self._switch_mark = self._switch_steps = 0  # the child's voluntary context switches, steps, at the last look
        self._steps = 0
        self._cpu_mark = (0, 0.0)  # (steps, child CPU s) at the start of the CPU window
        self._stepped = (0.0, 0.0)  # (s of wall time inside step(), s of simulated time: the dt summed) since load
        self._scheduled_mark: tuple[float | None, float] = (None, 0.0)  # (child's, our run delay) at load
        self._tasks = 0
        self._cpu: int | None = None  # the CPU this thread and the child are kept on (_follow_parent)
        self._affinity: set[int] | None = None  # this thread's CPUs before it was pinned
        self._pinned_thread = 0  # the native id of the thread pinned (the one that steps)
        self._shared_mark = (0.0, 0.0, 0.0)  # _cpu_use() when the pair was pinned or last looked at
        self._jail: pool.Jail | None = None  # the jail whose zygote forked the child
        self.reference = ""  # how the file reached the lab's own controllers while it loaded ('' if it did not)
        self._sleeping = 0.0  # s the live child's steps slept, at the last look (added to _SLEPT when it ends)

    # the Controller protocol
    def reset(self) -> None:
        self._faulted = ""  # error_recovery: the next call starts a fresh child
        if self._alive():
            self._call(b"R", b"", "reset")

    def step(
        self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float
    ) -> np.ndarray:
        self._ensure()
        request = self._slot.step_in
        request[:6] = wrench_ee.ravel()[:6]
        request[6:22] = transform_ee_to_base.ravel()[:16]
        request[22:-1] = wire.param_values(params)
        request[-1] = dt
        started = time.perf_counter()
        _kind, size = self._call(b"S", None, "step")
        self._account(time.perf_counter() - started, dt)
        if size != wire.TWIST_BYTES:
            self._fault(f"{self.name}.step returned {size // 8} numbers, expected 6 = [vx, vy, vz, wx, wy, wz]")
        twist = self._slot.twist_out.copy()  # out of the slot first, then checked: the child cannot change it now
        if not all(map(math.isfinite, twist.tolist())):
            self._fault(f"{self.name}.step returned a non-finite twist {twist.tolist()}")
        return twist

    def start(self, params: LiftingParams, force: float) -> str:
        if not (self._faulted and not self.has_start):  # a stopped file without start() still has the lab's
            self._ensure()
        if not self.has_start:
            return start_lifting(params, force) if self.stand_in else f"{self.name} has no start(): nothing was started"
        return self._service(b"A", wire.params_to_floats(params) + [float(force)], params, "start")

    def stop(self, params: LiftingParams) -> str:
        if not (self._faulted and not self.has_stop):
            self._ensure()
        if not self.has_stop:
            return stop_lifting(params) if self.stand_in else f"{self.name} has no stop(): nothing was stopped"
        return self._service(b"O", wire.params_to_floats(params), params, "stop")

    def close(self) -> None:
        """End the child (the end of its input, then SIGKILL if it lingers)."""
        pid, self.pid = self.pid, None
        handles = self.__dict__
        for name in _HANDLES:  # the child's pipes and slot: gone until the next child
            handle = handles.pop(name, None)
            if isinstance(handle, int):
                try:
                    os.close(handle)
                except OSError:
                    pass
        slot = handles.pop("_slot", None)
        if slot is not None:
            slot.close()
        if self._sleeping > 0:
            key = (str(self.path), self.class_name)
            _SLEPT[key] = _SLEPT.get(key, 0.0) + self._sleeping
            self._sleeping = 0.0
        if self._affinity is not None and self._pinned_thread == threading.get_native_id():
            watch.keep_on_cpu([0], self._affinity)  # this thread as it was before the child
        self._cpu = None
        if pid is not None and self._owner == os.getpid():
            self._finish(grace=0.5)

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass

    def __getstate__(self) -> dict:  # a copy in another process starts its own child
        state = dict(self.__dict__)
        for name in (*_HANDLES, "_slot", "_poll"):
            state.pop(name, None)
        state.update(pid=None, _owner=0, _jail=None, _cpu=None, _affinity=None, _pinned_thread=0, _sleeping=0.0)
        return state

    def load(self) -> SandboxedController:
        """Start the child and import the file now (a file that cannot be loaded fails here)."""
        self._ensure()
        return self

    # the child's life
    def _alive(self) -> bool:
        return self.pid is not None and self._owner == os.getpid()

    def _tree(self) -> list[int]:
        """The child's processes (this process's pids)."""
        return self._jail.item_tree() if self._jail is not None and self._alive() else []

    def _cpu_time(self) -> float:
        """s of CPU used by the child's processes (all threads)."""
        return watch.cpu_time(self._tree())

    def _ensure(self) -> None:
        if self._alive():
            return
        if self._faulted:  # no respawn at every step of the live loop: wait for reset (error_recovery)
            raise ControllerFault(self._faulted)
        slept = _SLEPT.get((str(self.path), self.class_name), 0.0)
        if slept > self.budget.file_sleep:  # the file's budget of sleeping is spent: no more of its items
            raise ControllerFault(
                f"your step() slept {slept:.1f} s in this file's earlier items (sleeping?): beyond the file's "
                f"budget of {self.budget.file_sleep:g} s, its later items are not run"
            )
        self.pid, self._jail = None, None  # a child of another process (fork) is not ours to talk to
        self._spawn()
        _kind, size = self._call(b"L", self._load_request, "load", self.budget.load_timeout)
        reply = self._slot.answer_payload(min(size, wire.MAX_TEXT))
        self.has_start, self.has_stop = bool(reply[:1] == b"\1"), bool(reply[1:2] == b"\1")
        if reach := wire.text(reply[2:]):
            self.reference = f"{self.path} is the lab's reference controller, not a submission: it {reach}"
        self._steps = 0
        tree = self._tree()
        self._switch_mark, self._switch_steps = watch.voluntary_switches(tree), 0
        self._tasks = watch.count_tasks(tree)
        if self._tasks > 1:  # the child is one thread when the file starts loading (one BLAS thread)
            self._fault(
                f"importing {self.path} started a thread or a process ({self._tasks - 1} more): a controller "
                "runs in its one thread, each step returns the twist"
            )
        self._cpu_mark = (0, watch.cpu_time(tree))
        self._stepped = (0.0, 0.0)
        self._scheduled_mark = (watch.scheduled_time(tree), watch.own_run_delay())
        self._cpu = None
        self._follow_parent()

    def _spawn(self) -> None:
        """A fresh child for this controller, forked by its file's zygote (pool.py), with its own
        slot and pipes: fd SLOT_FD, WAKE_CHILD_FD, WAKE_PARENT_FD and stderr in the child."""
        self._load_request = str(self.path).encode() + b"\0" + self.source.encode()
        slot_fd = os.memfd_create("controller-slot", os.MFD_CLOEXEC | os.MFD_ALLOW_SEALING)
        os.ftruncate(slot_fd, wire.slot_bytes(len(self._load_request)))
        # its size fixed for good: a child that shrank it would fault the parent's reads (SIGBUS)
        fcntl.fcntl(slot_fd, fcntl.F_ADD_SEALS, fcntl.F_SEAL_SHRINK | fcntl.F_SEAL_GROW | fcntl.F_SEAL_SEAL)
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        errors_r, errors_w = os.pipe()
        try:
            jail, self.pid = pool.fork(
                self.budget, self.class_name, self.sandboxed, [slot_fd, to_child_r, from_child_w, errors_w]
            )
        except pool.JailError as exc:
            for fd in (to_child_r, to_child_w, from_child_r, from_child_w, errors_r, errors_w, slot_fd):
                os.close(fd)
            raise ControllerFault(str(exc)) from None
        finally:
            for fd in (to_child_r, from_child_w, errors_w):  # the child's ends: it has its own copies
                try:
                    os.close(fd)
                except OSError:
                    pass
        self._jail = jail
        self._owner = os.getpid()
        self._to_child, self._from_child, self._errors = to_child_w, from_child_r, errors_r
        self._slot = wire.Slot(slot_fd)
        os.close(slot_fd)  # the map stays
        self._seq = 0
        # our ends only (a pipe's two ends are two files): a child that never reads its wake-ups
        # cannot block a write here, nor can anything the child does make a read here block
        for fd in (to_child_w, from_child_r, errors_r):
            os.set_blocking(fd, False)
        self._poll = select.poll()
        self._poll.register(from_child_r, select.POLLIN)

    def _finish(self, grace: float) -> int | None:
        """The child ended (its input closed: up to `grace` s, then killed) and its jail given back; its wait status."""
        jail, self._jail = self._jail, None
        if jail is None:
            return None
        status = jail.end_item(grace)
        pool.give_back(jail)
        return status

    # one request, one answer
    def _call(self, op: bytes, payload: bytes | None, what: str, timeout: float | None = None) -> tuple[bytes, int]:
        """One request (a step's floats are in the slot already: payload None) and its answer's
        (kind, payload bytes); an error answer is a fault."""
        if op not in (b"L", b"S"):  # step() has made sure already
            self._ensure()
        self._seq += 1
        seq = self._seq
        if payload is None:
            wire.HEADER.pack_into(self._slot.memory, wire.REQUEST_AT, seq, op, wire.STEP_FLOATS * 8)
        else:
            self._slot.put_request(seq, op, payload)
        try:
            os.write(self._to_child, b"\1")
        except BlockingIOError:
            self._fault(f"{self.name}.{what}: the controller's process does not take its requests")
        except OSError:
            self._fault(f"{self.name}.{what}: {self._death()}")
        kind, size = self._answer(seq, time.perf_counter() + (timeout or self.budget.step_timeout), what)
        if size > wire.MAX_REPLY:
            self._fault(f"{self.name}.{what} answered {size} bytes (at most {wire.MAX_REPLY})")
        if kind == b"e":
            body = wire.text(self._slot.answer_payload(size))
            self._fault(body if what == "load" else f"{self.name}.{what} {body}")
        if kind not in (b"k", b"p"):
            self._fault(f"{self.name}.{what}: the controller's process answered nonsense")
        return kind, size

    def _answer(self, seq: int, deadline: float, what: str) -> tuple[bytes, int]:
        """Wait for the answer to request `seq` (a wake-up byte, then its sequence number in the slot)."""
        while True:
            try:  # the child often answered already (it runs as soon as it is woken): no poll then
                woken = os.read(self._from_child, 64)
            except BlockingIOError:  # not yet
                left = deadline - time.perf_counter()
                if left <= 0 or not self._poll.poll(left * 1e3 + 1):
                    waited = self.budget.load_timeout if what == "load" else self.budget.step_timeout
                    self._fault(f"{self.name}.{what} did not answer within {waited:g} s (wall clock): stopped")
                continue
            if not woken:
                self._fault(
                    f"importing {self.path} failed: {self._death()}"
                    if what == "load"
                    else f"{self.name}.{what}: {self._death()}"
                )
            answered, kind, size = self._slot.answer()
            if answered == seq:
                return kind, size

    def _service(self, op: bytes, values: list[float], params: LiftingParams, what: str) -> str:
        _kind, size = self._call(op, np.asarray(values, float).tobytes(), what)
        reply = self._slot.answer_payload(size)
        count = len(wire.PARAM_FIELDS) * 8
        new = np.frombuffer(reply[:count], dtype=np.float64) if len(reply) >= count else np.array([np.nan])
        fields = dict(zip(wire.PARAM_FIELDS, new.tolist()))
        f_n_min, f_n_band, running = (
            fields.get("f_n_min", np.nan),
            fields.get("f_n_band", np.nan),
            fields.get("running", np.nan),
        )
        # held to what the parameter server takes (LIFTING_RANGES): refused, the call fails and
        # nothing changes (the child lives on: its own copy is all it changed)
        refusal = lifting_refusal({"f_n_min": f_n_min, "f_n_band": f_n_band})
        if running not in (0.0, 1.0):
            refusal = f"running must be True or False, got {running!r}"
        if refusal:
            raise ControllerFault(f"{self.name}.{what} set a lifting parameter the lab refuses: {refusal}")
        # only what the services own changes; the other fields belong to the parameter server
        params.f_n_min, params.f_n_band, params.running = f_n_min, f_n_band, bool(running)
        return wire.text(reply[count:])

    # watching the child
    def _follow_parent(self) -> None:
        """Keep this thread and the child on one CPU, the one this thread runs on now. They take
        turns (this thread waits while the child steps), so each wake-up is a switch on that CPU,
        never a wake-up sent to another, perhaps halted, CPU: unpinned, the scheduler wakes each side
        on whichever CPU is idle, which on idle cores is the other one, twice a step
        (docs/sandbox.md, "Figures"). Once a SHARED_WINDOW: a pair whose CPU spent more than
        SHARED_SHARE of it on other work (another pair, other programs) is let go, for the scheduler
        to move it, and pinned again where it is at the next look. CPUs set on this thread by
        anyone else are taken as its own."""
        mine = os.sched_getaffinity(0)
        if self._cpu is not None and mine != {self._cpu}:  # another thread steps, or the CPUs were set
            self._cpu = None
        if self._cpu is not None and self._shared():
            self._let_go()
            return
        cpu = watch.current_cpu()
        if cpu is None or cpu == self._cpu:
            return
        if self._cpu is None:
            self._affinity, self._pinned_thread = mine, threading.get_native_id()
        watch.keep_on_cpu([0, *self._tree()], {cpu})
        self._cpu = cpu
        self._shared_mark = self._cpu_use(cpu)

    def _cpu_use(self, cpu: int) -> tuple[float, float, float]:
        """(wall s, s CPU `cpu` was busy, s of CPU this thread and the child used)."""
        return time.perf_counter(), watch.cpu_busy_time(cpu), watch.own_cpu_time() + self._cpu_time()

    def _shared(self) -> bool:
        """Whether, over the last SHARED_WINDOW at least, the pair's CPU did others' work more than
        SHARED_SHARE of the time (/proc's clock ticks: a window of many ticks)."""
        assert self._cpu is not None
        wall, busy, ours = self._cpu_use(self._cpu)
        wall0, busy0, ours0 = self._shared_mark
        if wall - wall0 < SHARED_WINDOW:
            return False
        self._shared_mark = (wall, busy, ours)
        return (busy - busy0) - (ours - ours0) > SHARED_SHARE * (wall - wall0)

    def _let_go(self) -> None:
        """This thread and the child back on the CPUs this thread had before it was pinned."""
        if self._affinity is not None:
            watch.keep_on_cpu([0, *self._tree()], self._affinity)
        self._cpu = None

    def _account(self, wall: float, dt: float) -> None:
        budget = self.budget
        self._steps += 1
        walls, simulated = self._stepped
        self._stepped = (walls + wall, simulated + (dt if math.isfinite(dt) and dt > 0 else 0.0))
        if self._steps % budget.check_every and wall < budget.slow_step:
            return
        self._follow_parent()
        tree = self._tree()
        self._check_sleeping(tree)
        tasks = watch.count_tasks(tree)
        if tasks > self._tasks:
            self._fault(
                f"{self.name} started a thread or a process ({tasks - self._tasks} more): a controller runs "
                "in its one thread, each step returns the twist"
            )
        # between two steps the child blocks once, reading the next request; any other voluntary
        # context switch is a sleep or blocking I/O inside step() (being preempted is involuntary)
        switches = watch.voluntary_switches(tree)
        extra = switches - self._switch_mark - (self._steps - self._switch_steps)
        if self._steps % budget.check_every == 0:
            self._switch_mark, self._switch_steps = switches, self._steps
        if extra > budget.max_sleeps:
            self._fault(
                f"{self.name}.step sleeps or blocks: {extra} times within {budget.check_every} steps "
                f"(at most {budget.max_sleeps}; the loop runs at 1 kHz, a step must return, not wait); "
                f"last step {wall * 1e3:.1f} ms"
            )
        steps, cpu = self._cpu_mark
        if self._steps - steps >= budget.window:
            used = watch.cpu_time(tree) - cpu
            mean = used / (self._steps - steps)
            if mean > budget.mean_cpu:
                self._fault(
                    f"{self.name}.step used {mean * 1e3:.2f} ms of CPU per step over {self._steps - steps} steps "
                    f"(budget {budget.mean_cpu * 1e3:g} ms)"
                )
            self._cpu_mark = (self._steps, used + cpu)

    def _check_sleeping(self, tree: list[int]) -> None:
        """Stop a child whose step() sleeps through more than `sleep_ratio` times its simulated
        time plus `sleep_grace` (a sleep costs no CPU: neither RLIMIT_CPU nor `mean_cpu` sees it).
        Sleeping is the steps' wall time less what the child ran or waited for a CPU and what this
        thread waited for one (/proc's schedstat): a loaded machine makes steps slow by waiting,
        which is not counted, so load never fails an honest file. Without schedstat, the steps'
        whole wall time counts against `no_schedstat_ratio` times the simulated time."""
        budget = self.budget
        walls, simulated = self._stepped
        child_mark, own_mark = self._scheduled_mark
        scheduled = watch.scheduled_time(tree)
        if scheduled is None or child_mark is None:
            sleeping, allowed = walls, budget.no_schedstat_ratio * simulated + budget.sleep_grace
        else:
            sleeping = walls - (scheduled - child_mark) - (watch.own_run_delay() - own_mark)
            allowed = budget.sleep_ratio * simulated + budget.sleep_grace
        self._sleeping = max(sleeping - (allowed - budget.sleep_grace), 0.0)  # what counts against the file
        if sleeping > allowed:
            self._fault(
                f"your step() took {walls:.1f} s of wall time in {self._steps} steps (sleeping?): "
                f"{sleeping:.1f} s of it neither running nor waiting for a CPU, for {simulated:.3f} s "
                f"of simulated time (at most {budget.sleep_ratio:g} x the simulated time + {budget.sleep_grace:g} s)"
            )

    def _death(self) -> str:
        """Why the child is gone (its exit code or signal), with what it said on stderr."""
        status = self._finish(grace=1.0) if self._alive() else None
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
