"""The simulation process and its supervisor: the 1 kHz loop runs in a process of its own, so the
server's Python (HTTP, WebSockets, the 3D view) never holds the interpreter lock the loop needs.

- start: the supervisor forks the process from its pristine world (numba kernels compiled, robot
  model loaded), so the child starts in milliseconds. The child closes every socket it inherited
  (the server's listening socket and client connections stay the server's alone).
- snapshot(): the child publishes the snapshot and the loop's figures after every step into shared
  memory (app/runtime/shared_snapshot.py); the server reads them with no round trip.
- call(fn, *args): one pickle of (fn, args) down a pipe; the loop runs fn(world, *args) between
  two steps and sends back one pickle of the result or the exception. fn must be a module-level
  function (app/lab/commands.py) so it travels by name.
- one watchdog: should the process die (a crash in native code, a kill, a loop that ended), the
  supervisor notices within `watch_period`, fails the calls in flight with `SimulationRestarting`,
  records why and forks a fresh process from its pristine world (the state is lost, as when a real
  robot's controller restarts). A loop that stops ticking for `stall_timeout` is killed and restarted.
"""

from __future__ import annotations

import ctypes
import itertools
import math
import multiprocessing
import os
import pickle
import signal
import stat
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import contextmanager
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from typing import Any, Generic, TypeVar

from app.runtime.loop import LoopStats, Published, SharedSeconds, SimulationLoop, raise_priority
from app.runtime.sample_ring import SampleRing
from app.runtime.shared_snapshot import SharedSnapshot
from app.runtime.simulated import Simulated

_FORK = multiprocessing.get_context("fork")
T = TypeVar("T")
S = TypeVar("S")  # the world's snapshot type


class SimulationRestarting(RuntimeError):
    """The simulation process ended (and is being restarted) while a call was waiting for it."""


@dataclass(frozen=True)
class Health:
    """The loop's figures plus what the supervisor knows."""

    stats: LoopStats
    alive: bool
    restarts: int  # simulation processes started after one died
    last_death: str


class SimulationProcess(Generic[S]):
    watch_period = 0.2  # s between the supervisor's looks at the process
    stall_timeout = 10.0  # s without a tick before a live process is declared stuck

    def __init__(self, world: Simulated[S], realtime: bool = True) -> None:
        self.world = world  # the pristine world each (re)started process begins from
        self.realtime = realtime
        self.restarts = 0
        self.last_death = ""
        self._shared: SharedSnapshot[Published[S]] = SharedSnapshot(Published(world.snapshot(), LoopStats()))
        self._shared.write(Published(world.snapshot(), LoopStats()))
        self._ids = itertools.count()
        self._pending: dict[int, Future] = {}
        self._lock = threading.Lock()  # _pending, _conn, _process, sending
        self._process: BaseProcess | None = None
        self._conn: Connection | None = None
        self._stop = threading.Event()
        # the finest spacing (s of wall clock) between two steps that a reader needs now, and between
        # two published snapshots (read by the loop of every process forked from here:
        # app/runtime/loop.py, idle batches); a reader of every step's F_ext needs only the first
        self._granularity = _FORK.RawValue("d", math.inf)
        self._snapshot_spacing = _FORK.RawValue("d", math.inf)
        self.wrenches = SampleRing()  # every step's F_ext (a 1 kHz subscriber's source)
        self._needed: Counter[tuple[float, bool]] = Counter()  # (period, of snapshots) -> readers
        self._needed_lock = threading.Lock()

    # --- life cycle -------------------------------------------------------------------------
    def start(self) -> None:
        """Step once here (compiles the numba kernels once, for every fork), then fork the loop."""
        if self._process is None:
            self.world.step()
            self._spawn()
            threading.Thread(target=self._watch, name="sim-supervisor", daemon=True).start()

    def _spawn(self) -> None:
        parent_end, child_end = _FORK.Pipe()
        process = _FORK.Process(
            target=_child_main,
            args=(
                self.world,
                self.realtime,
                self._shared,
                child_end,
                parent_end,
                self._granularity,
                self._snapshot_spacing,
                self.wrenches,
            ),
            name="hri-lab-sim",
            daemon=True,
        )
        process.start()
        child_end.close()
        with self._lock:
            self._conn, self._process = parent_end, process
        self._receiver = threading.Thread(target=self._receive, args=(parent_end,), name="sim-results", daemon=True)
        self._receiver.start()

    def _watch(self) -> None:
        ticks, since = -1, time.monotonic()
        while not self._stop.wait(self.watch_period):
            process = self._process
            if process is None:
                continue
            now_ticks = self._shared.read().stats.ticks
            if now_ticks != ticks:
                ticks, since = now_ticks, time.monotonic()
            elif process.is_alive() and time.monotonic() - since > self.stall_timeout:
                process.kill()  # stuck: restarted below once it is gone
                process.join(timeout=2.0)
            if not process.is_alive() and not self._stop.is_set():
                self.last_death = self._shared.read().stats.fatal or _describe_exit(process.exitcode)
                self.restarts += 1
                self._receiver.join(timeout=2.0)  # the answers it sent before it died are read first (EOF)
                self._fail_pending(SimulationRestarting(f"the simulation restarted ({self.last_death}); call again"))
                self._spawn()
                ticks, since = -1, time.monotonic()

    def stop(self) -> None:
        self._stop.set()
        with self._lock:
            process, conn = self._process, self._conn
            self._process = None
            if process is None:
                return
            assert conn is not None  # set together with the process (_spawn)
            try:
                conn.send_bytes(b"")  # asks the child to stop its loop and exit
            except OSError:
                pass
        process.join(timeout=2.0)
        if process.is_alive():
            process.kill()
            process.join(timeout=2.0)
        self._receiver.join(timeout=2.0)  # the child gone, its answers read to the end (EOF) before the pipe closes
        conn.close()
        self._fail_pending(SimulationRestarting("the simulation was stopped"))

    @property
    def pid(self) -> int | None:
        process = self._process
        return process.pid if process is not None else None

    @contextmanager
    def needs(self, period: float, snapshots: bool = True) -> Iterator[None]:
        """While the block runs, a reader needs the loop to step at least every `period` s of wall
        clock (an idle loop wakes that often) and, unless `snapshots` is false (a reader of every
        step's F_ext, app/runtime/sample_ring.py), a fresh snapshot as often (a topic stream at
        1/period Hz, a recording)."""
        with self._needed_lock:
            self._needed[(period, snapshots)] += 1
            self._publish_needs()
        try:
            yield
        finally:
            with self._needed_lock:
                self._needed[(period, snapshots)] -= 1
                if not self._needed[(period, snapshots)]:
                    del self._needed[(period, snapshots)]
                self._publish_needs()

    def _publish_needs(self) -> None:
        self._granularity.value = min((period for period, _ in self._needed), default=math.inf)
        self._snapshot_spacing.value = min((period for period, of in self._needed if of), default=math.inf)

    # --- talking to the world ---------------------------------------------------------------
    def submit(self, fn: Callable[..., T], *args: object) -> Future[T]:
        """Run fn(world, *args) in the simulation between two steps; the future holds its result
        or its exception."""
        future: Future[T] = Future()
        with self._lock:
            if self._process is None:  # not started (or stopped): nobody else steps this world
                try:
                    future.set_result(fn(self.world, *args))
                except Exception as exc:  # noqa: BLE001 - handed back to the caller
                    future.set_exception(exc)
                return future
            try:
                data = pickle.dumps((fn, args))
            except Exception as exc:  # noqa: BLE001 - e.g. a lambda: say so at once
                future.set_exception(TypeError(f"cannot send {fn!r} to the simulation process: {exc}"))
                return future
            call_id = next(self._ids)
            self._pending[call_id] = future
            conn = self._conn
            assert conn is not None  # set together with the process (_spawn), which is not None here
            try:
                conn.send_bytes(call_id.to_bytes(8, "little") + data)
            except OSError:  # the child is gone (the watchdog restarts it)
                del self._pending[call_id]
                future.set_exception(SimulationRestarting("the simulation process is gone; it is being restarted"))
        return future

    def call(self, fn: Callable[..., T], *args: object, timeout: float = 10.0) -> T:
        """fn(world, *args) run in the simulation between two steps; its result (or its exception)."""
        return self.submit(fn, *args).result(timeout=timeout)

    def snapshot(self) -> S:
        """The latest published snapshot."""
        return self._shared.read().snapshot

    def health(self) -> Health:
        process = self._process
        return Health(
            self._shared.read().stats, process is not None and process.is_alive(), self.restarts, self.last_death
        )

    # --- answers ----------------------------------------------------------------------------
    def _receive(self, conn: Connection) -> None:
        while True:
            try:
                message = conn.recv_bytes()
            except (EOFError, OSError, TypeError):  # TypeError: the pipe closed under the read (a stop
                return  # whose wait for this thread ran out)
            call_id, ok = int.from_bytes(message[:8], "little"), message[8] == 1
            try:
                value = pickle.loads(message[9:])
            except Exception as exc:  # noqa: BLE001 - e.g. an exception type that does not rebuild here
                ok, value = (
                    False,
                    RuntimeError(f"the simulation's answer could not be read: {type(exc).__name__}: {exc}"),
                )
            with self._lock:
                future = self._pending.pop(call_id, None)
            if future is not None:
                (future.set_result if ok else future.set_exception)(value)

    def _fail_pending(self, error: Exception) -> None:
        with self._lock:
            pending, self._pending = self._pending, {}
        for future in pending.values():
            future.set_exception(error)


def _describe_exit(code: int | None) -> str:
    if code is not None and code < 0:
        return f"simulation process killed by {signal.Signals(-code).name}"
    return f"simulation process exited with code {code}"


# --- the child ------------------------------------------------------------------------------
def name_this_process(name: str) -> None:
    """The name `ps`, `top` and /proc/PID/comm show for a forked child (Linux: at most 15 bytes),
    so the server's two children tell apart: "hri-lab-sim" and "hri-lab-camera"."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(15, name.encode()[:15], 0, 0, 0)  # PR_SET_NAME
    except (OSError, AttributeError):
        pass  # a name only: nothing depends on it but what a person or a test reads


def close_inherited_sockets(keep: int) -> None:
    """Close every socket this fork inherited from the server but `keep` (our pipe)."""
    for name in os.listdir("/proc/self/fd"):
        fd = int(name)
        if fd == keep:
            continue
        try:
            if stat.S_ISSOCK(os.fstat(fd).st_mode):
                os.close(fd)
        except OSError:
            pass


def _child_main(
    world: Simulated[Any],
    realtime: bool,
    shared: SharedSnapshot[Published[Any]],
    conn: Connection,
    parent_end: Connection,
    granularity: SharedSeconds,
    snapshot_spacing: SharedSeconds,
    wrenches: SampleRing,
) -> None:
    """Run the loop, publish its snapshots, serve the supervisor's calls until told to stop (or
    the supervisor is gone: the pipe ends)."""
    parent_end.close()
    name_this_process("hri-lab-sim")
    close_inherited_sockets(conn.fileno())
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C is the server's to handle; it stops us
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if realtime:  # every thread of this process (they inherit it), so none holding the
        raise_priority()  # interpreter lock is preempted while the loop waits for it
    sys.setswitchinterval(0.0005)  # s; the loop waits at most this long for the lock
    send_lock = threading.Lock()

    def reply(call_id: int, ok: bool, value: object) -> None:
        try:
            data = pickle.dumps(value)
        except Exception as exc:  # noqa: BLE001 - the value does not pickle: say what it was
            ok, data = (
                False,
                pickle.dumps(RuntimeError(f"the result could not be sent back: {type(exc).__name__}: {exc}")),
            )
        with send_lock:
            conn.send_bytes(call_id.to_bytes(8, "little") + (b"\x01" if ok else b"\x00") + data)

    def sample(stepped: Any) -> None:  # a world with F_ext (the lifting world's)
        wrenches.append(stepped.time, stepped.wrench_ee)

    has_wrench = hasattr(world, "wrench_ee")  # the lifting world's F_ext; the mobile world has none
    loop = SimulationLoop(
        world,
        shared.write,
        reply,
        realtime=realtime,
        granularity=granularity,
        snapshot_spacing=snapshot_spacing,
        sample=sample if has_wrench else None,
    )

    def receive() -> None:
        while True:
            try:
                message = conn.recv_bytes()
            except (EOFError, OSError):
                break
            if not message:  # the supervisor's stop
                break
            call_id = int.from_bytes(message[:8], "little")
            try:
                fn, args = pickle.loads(message[8:])
            except Exception as exc:  # noqa: BLE001 - e.g. a function this process cannot import
                reply(call_id, False, exc)
                continue
            loop.submit(call_id, fn, args)
        loop.stop()

    threading.Thread(target=receive, name="sim-commands", daemon=True).start()
    try:
        loop.run()
    except BaseException:  # noqa: BLE001 - `fatal` is published; exit so the supervisor restarts us
        os._exit(70)
