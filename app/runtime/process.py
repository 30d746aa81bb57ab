"""The real-time loop in its own process, so the server's Python (HTTP, WebSockets, the 3D view)
never holds the interpreter lock the 1 kHz loop needs.

The parent forks the process from its world (numba kernels compiled, robot model loaded), so the
child starts in milliseconds and shares the parent's memory pages until it writes them. Then:
- snapshots: the child writes one after every step into shared memory (app/shared_snapshot.py);
  the server reads it with no round trip;
- commands: `call(fn, *args)` pickles (fn, args) down a pipe; the child's SimulationLoop runs
  fn(world, *args) between two steps and sends back the result or the exception. fn must be a
  module-level function (app/world_commands.py, or a method of World), so it pickles by name;
- health: a loop query (`stats`) runs in the child beside the loop, not between its steps;
- faults: the child's own watchdog restarts a dead loop thread on the same world; should the whole
  process die (a crash in native code, a kill), the parent notices within `watch_period`, fails the
  calls in flight, reports why and forks a fresh one from its pristine world (the state is lost,
  as when a real robot's controller restarts).
"""
from __future__ import annotations

import itertools
import multiprocessing
import pickle
import signal
import sys
import threading
from concurrent.futures import Future
from dataclasses import replace
from multiprocessing.connection import Connection
from typing import Any, Callable

from sim.world import Snapshot, World

from app.runtime.shared_snapshot import SharedSnapshot
from app.runtime.loop import LoopStats, SimulationLoop, raise_priority, resolve

_FORK = multiprocessing.get_context("fork")


class SimulationDied(RuntimeError):
    """The simulation process ended while a call was waiting for it."""


class SimulationProcess:
    watch_period = 0.2  # s between the parent's looks at the child

    def __init__(self, world: World, realtime: bool = True) -> None:
        self.world = world  # the pristine world each (re)started process begins from
        self.realtime = realtime
        self.restarts = 0  # times the whole process was restarted
        self.last_death = ""
        self._shared = SharedSnapshot(world.snapshot())
        self._shared.write(world.snapshot())
        self._ids = itertools.count()
        self._pending: dict[int, Future] = {}
        self._lock = threading.Lock()  # _pending, _conn, sending
        self._process: multiprocessing.Process | None = None
        self._conn: Connection | None = None
        self._stop = threading.Event()

    # --- life cycle -------------------------------------------------------------------------
    def start(self) -> None:
        """Step once here (compiles the numba kernels once, for every fork), then fork the loop."""
        if self._process is None:
            self.world.step()
            self._spawn()
            threading.Thread(target=self._watch, name="sim-process-watchdog", daemon=True).start()

    def _spawn(self) -> None:
        parent_end, child_end = _FORK.Pipe()
        process = _FORK.Process(target=_child_main, args=(self.world, self.realtime, self._shared, child_end, parent_end),
                                name="hri-lab-sim", daemon=True)
        process.start()
        child_end.close()
        with self._lock:
            self._conn, self._process = parent_end, process
        threading.Thread(target=self._receive, args=(parent_end,), name="sim-process-results", daemon=True).start()

    def _watch(self) -> None:
        while not self._stop.wait(self.watch_period):
            process = self._process
            if process is not None and not process.is_alive() and not self._stop.is_set():
                self.last_death = _describe_exit(process.exitcode)
                self.restarts += 1
                self._fail_pending(SimulationDied(self.last_death))
                self._spawn()

    def stop(self) -> None:
        self._stop.set()
        with self._lock:
            process, conn = self._process, self._conn
            self._process = None
            if process is None:
                return
            try:
                conn.send(None)  # asks the child to stop its loop and exit
            except OSError:
                pass
        process.join(timeout=2.0)
        if process.is_alive():
            process.kill()
            process.join(timeout=2.0)
        conn.close()
        self._fail_pending(SimulationDied("the simulation was stopped"))

    @property
    def alive(self) -> bool:
        process = self._process
        return process is not None and process.is_alive()

    # --- talking to the world ---------------------------------------------------------------
    def submit(self, fn: Callable[..., Any], *args: Any, target: str = "world") -> Future:
        """Run fn(world, *args) in the simulation process between two steps (target "loop":
        fn(loop, *args) beside the loop); the future holds its result or its exception."""
        future: Future = Future()
        with self._lock:
            if self._process is None:  # not started (or stopped): nobody else steps this world
                if target == "world":
                    resolve(future, fn, self.world, *args)
                else:
                    future.set_exception(SimulationDied("the simulation is not running"))
                return future
            try:
                data = pickle.dumps((fn, args))
            except Exception as exc:  # noqa: BLE001 - e.g. a lambda: say so at once
                future.set_exception(TypeError(f"cannot send {fn!r} to the simulation process: {exc}"))
                return future
            call_id = next(self._ids)
            self._pending[call_id] = future
            try:
                self._conn.send((call_id, target, data))
            except OSError as exc:  # the child is gone (the watchdog restarts it)
                del self._pending[call_id]
                future.set_exception(SimulationDied(str(exc)))
        return future

    def call(self, fn: Callable[..., Any], *args: Any, timeout: float = 10.0) -> Any:
        return self.submit(fn, *args).result(timeout=timeout)

    def snapshot(self) -> Snapshot:
        return self._shared.read()

    def stats(self) -> LoopStats:
        """The child's loop figures (a dead process reports alive = False and its restart)."""
        try:
            stats = self.submit(SimulationLoop.stats, target="loop").result(timeout=2.0)
        except Exception:  # noqa: BLE001 - dead or stuck: say so
            stats = LoopStats(ticks=self._shared.written, rate_hz=0.0, lateness_p50=0.0, lateness_p99=0.0, overruns=0,
                              alive=False)
        return replace(stats, restarts=stats.restarts + self.restarts,
                       last_death=self.last_death if self.last_death else stats.last_death)

    # --- results ----------------------------------------------------------------------------
    def _receive(self, conn: Connection) -> None:
        while True:
            try:
                call_id, ok, data = conn.recv()
            except (EOFError, OSError):
                return
            try:
                value = pickle.loads(data)
            except Exception as exc:  # noqa: BLE001 - e.g. an exception type that does not rebuild here
                ok, value = False, RuntimeError(f"the simulation's answer could not be read: {type(exc).__name__}: {exc}")
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
def _child_main(world: World, realtime: bool, shared: SharedSnapshot, conn: Connection, parent_end: Connection) -> None:
    """Run the loop, publish its snapshots, serve the parent's calls until told to stop (or the
    parent is gone: the pipe ends)."""
    parent_end.close()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C is the server's to handle; it stops us
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if realtime:  # every thread of this process (they inherit it), so none holding the
        raise_priority()  # interpreter lock is preempted while the loop waits for it
    sys.setswitchinterval(0.0005)  # s; the loop waits at most this long for the lock
    loop = SimulationLoop(world, realtime=realtime, publish=shared.write)
    send_lock = threading.Lock()

    def reply(call_id: int, ok: bool, value: Any) -> None:
        try:
            data = pickle.dumps(value)
        except Exception as exc:  # noqa: BLE001 - the value does not pickle: say what it was
            ok, data = False, pickle.dumps(RuntimeError(f"the result could not be sent back: {type(exc).__name__}: {exc}"))
        with send_lock:
            conn.send((call_id, ok, data))

    loop.start()
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            break
        if message is None:
            break
        call_id, target, data = message
        try:
            fn, args = pickle.loads(data)
        except Exception as exc:  # noqa: BLE001 - e.g. a function this process cannot import
            reply(call_id, False, exc)
            continue
        if target == "loop":
            try:
                reply(call_id, True, fn(loop, *args))
            except Exception as exc:  # noqa: BLE001
                reply(call_id, False, exc)
            continue
        future = loop.submit(lambda w, fn=fn, args=args: fn(w, *args))
        future.add_done_callback(lambda f, call_id=call_id: reply(call_id, f.exception() is None,
                                                                  f.exception() or f.result()))
    loop.stop()
