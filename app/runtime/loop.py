"""The real-time loop: one thread owns the World and steps it at the control rate (1 kHz).

Other threads never touch the world: they `submit()` a function that the loop runs between two
steps (a lock-protected command queue) and read the latest `Snapshot`, published after every step.
A submitted function's answer comes once the step after it is published (so its effect is in the
snapshot). An exception in a submitted function goes back to its caller; the loop goes on.
The server runs this loop inside the simulation process (app/sim_process.py). An exception in
a step stops the robot (error state), not the loop. Should the thread die all the same, the
watchdog notices it within `watch_period`, records why, and starts a new one on the same world.
"""
from __future__ import annotations

import os
import queue
import threading
import time
from collections import deque
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Callable, TypeVar

from sim.world import Snapshot, World

T = TypeVar("T")


@dataclass
class LoopStats:
    """Timing (s) and health of the loop."""

    ticks: int
    rate_hz: float
    lateness_p50: float
    lateness_p99: float
    overruns: int  # periods skipped because the loop fell too far behind
    realtime_priority: bool = False
    alive: bool = True
    step_errors: int = 0  # steps that raised (the robot was stopped, the loop went on)
    last_step_error: str = ""
    restarts: int = 0  # loop threads (or processes) restarted after dying
    last_death: str = ""


class SimulationLoop:
    max_behind = 0.05  # s; further behind than this, the loop drops the missed periods
    watch_period = 0.2  # s between the watchdog's looks at the loop thread

    def __init__(self, world: World, realtime: bool = True, publish: Callable[[Snapshot], None] | None = None) -> None:
        """publish(snapshot) is called after every step (e.g. to share it with another process)."""
        self.world = world
        self.realtime = realtime
        self._publish = publish
        self._commands: queue.SimpleQueue[tuple[Callable[[World], object], Future]] = queue.SimpleQueue()
        self._snapshot_lock = threading.Lock()
        self._snapshot = world.snapshot()
        self._lateness: deque[float] = deque(maxlen=5000)
        self._ticks = 0
        self._overruns = 0
        self.step_errors = 0
        self.last_step_error = ""
        self.restarts = 0  # times the watchdog restarted a dead loop thread
        self.realtime_priority = False  # the loop thread runs SCHED_FIFO (when the system allows it)
        self.last_death = ""
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._started = 0.0

    # --- life cycle -------------------------------------------------------------------------
    def start(self) -> None:
        """Step once here (the first step compiles the simulation's numba kernels, which can take
        seconds on a fresh install), then hand the world to the loop thread, under a watchdog."""
        if self._thread is None:
            self._step()
            self._started = time.perf_counter()
            self._spawn()
            self._watchdog = threading.Thread(target=self._watch, name="sim-watchdog", daemon=True)
            self._watchdog.start()

    def _spawn(self) -> None:
        self._thread = threading.Thread(target=self._run, name="sim-loop", daemon=True)
        self._thread.start()

    def _watch(self) -> None:
        while not self._stop.wait(self.watch_period):
            if self._thread is not None and not self._thread.is_alive() and not self._stop.is_set():
                self.restarts += 1
                self._spawn()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None

    @property
    def alive(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    # --- talking to the world ---------------------------------------------------------------
    def submit(self, fn: Callable[[World], T]) -> Future:
        """Run fn(world) on the loop thread before the next step; the future holds its result."""
        future: Future = Future()
        if not self.alive:  # not running (e.g. before start): run here, nobody else steps
            resolve(future, fn, self.world)
            return future
        self._commands.put((fn, future))
        return future

    def call(self, fn: Callable[[World], T], timeout: float = 10.0) -> T:
        """submit() and wait for the result (re-raises fn's exception)."""
        return self.submit(fn).result(timeout=timeout)

    def snapshot(self) -> Snapshot:
        with self._snapshot_lock:
            return self._snapshot

    def stats(self) -> LoopStats:
        late = sorted(list(self._lateness))
        elapsed = time.perf_counter() - self._started if self._started else 0.0
        pick = (lambda q: late[min(len(late) - 1, int(q * len(late)))]) if late else (lambda q: 0.0)
        return LoopStats(
            ticks=self._ticks,
            rate_hz=self._ticks / elapsed if elapsed > 0 else 0.0,
            lateness_p50=pick(0.5),
            lateness_p99=pick(0.99),
            overruns=self._overruns,
            realtime_priority=self.realtime_priority,
            alive=self.alive,
            step_errors=self.step_errors,
            last_step_error=self.last_step_error,
            restarts=self.restarts,
            last_death=self.last_death,
        )

    # --- the loop ---------------------------------------------------------------------------
    def _run(self) -> None:
        if self.realtime:
            self.realtime_priority = raise_priority()
        try:
            self._tick_forever()
        except BaseException as exc:  # noqa: BLE001 - recorded; the watchdog starts a new thread
            self.last_death = f"{type(exc).__name__}: {exc}"

    def _tick_forever(self) -> None:
        period = self.world.config.dt
        next_tick = time.perf_counter()
        while not self._stop.is_set():
            done = self._drain_commands()
            try:
                self._step()
            finally:  # answered once their effect is in the snapshot (or the step failed)
                for future, ok, value in done:
                    (future.set_result if ok else future.set_exception)(value)
            if not self.realtime:
                continue
            next_tick += period
            now = time.perf_counter()
            if now - next_tick > self.max_behind:  # far behind (paused, overloaded): resync
                self._overruns += 1
                next_tick = now
            elif next_tick > now:
                time.sleep(next_tick - now)
            self._lateness.append(max(0.0, time.perf_counter() - next_tick))

    def _step(self) -> None:
        try:
            self.world.step()
        except Exception as exc:  # noqa: BLE001 - a simulation bug stops the robot, not the loop
            self.step_errors += 1
            self.last_step_error = f"{type(exc).__name__}: {exc}"
            self.world.arm.error = f"simulation error: {self.last_step_error}"
        snapshot = self.world.snapshot()
        with self._snapshot_lock:
            self._snapshot = snapshot
        if self._publish is not None:
            self._publish(snapshot)
        self._ticks += 1

    def _drain_commands(self) -> list[tuple[Future, bool, object]]:
        """Run the queued functions; their (future, ok, result or exception)."""
        done = []
        while True:
            try:
                fn, future = self._commands.get_nowait()
            except queue.Empty:
                return done
            try:
                done.append((future, True, fn(self.world)))
            except BaseException as exc:  # noqa: BLE001 - handed back to the caller, never kills the loop
                done.append((future, False, exc))


REALTIME_PRIORITY = 10  # SCHED_FIFO priority of the loop thread (1..99; libfranka's control thread asks for 80)


def raise_priority() -> bool:
    """Run the calling thread with real-time scheduling (SCHED_FIFO), as libfranka does for its
    control loop, when the system allows it (root or CAP_SYS_NICE); otherwise go on as before.
    The loop sleeps most of each period, and Linux caps real-time threads at 95 % of a core."""
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(REALTIME_PRIORITY))
        return True
    except (OSError, AttributeError):
        return False


def resolve(future: Future, fn: Callable[..., object], world: World, *args: object) -> None:
    """future <- fn(world, *args), its result or its exception."""
    try:
        future.set_result(fn(world, *args))
    except BaseException as exc:  # noqa: BLE001 - handed back to the caller
        future.set_exception(exc)
