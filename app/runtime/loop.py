"""The real-time loop: one thread of the simulation process owns the World and steps it at the
control rate (1 kHz).

Each tick: run the commands queued since the last tick (fn(world, *args)), step the world, publish
the snapshot together with the loop's figures (`Published`), then answer the commands — so a
command's answer arrives once its effect is in the published snapshot. An exception in a command
goes back to its caller; an exception in a step stops the robot (error state), not the loop.
Anything that escapes all the same ends the loop with `fatal` set: the process then exits and its
supervisor (app/runtime/process.py) starts a fresh one.

An idle lab sleeps: while nobody commands the robot (`World.commanded` is false) and no command has
come for `fine_hold` seconds (a command marked `reads_world`, a parameter's value read, does not
count: a page that reads a parameter every second leaves an idle lab idle), nothing needs 1 ms
granularity, so the loop wakes once per `batch_period` (or as often as the server's readers need a
fresh snapshot: `granularity`, e.g. a 50 Hz topic stream) and runs the periods that came due back to
back (the same steps, the same simulated time; only their wall-clock spacing changes), publishing
the last of them. A command wakes it at once and the loop is back at 1 ms granularity before the
command runs. Lateness is measured only at 1 ms granularity (`LoopStats.batched` counts the ticks
stepped in batches). An idle loop kept at 1 ms granularity only by a reader of every step's sample
(`sample`, a 1 kHz F_ext subscriber), with no reader of snapshots that needs them oftener than
`batch_period` (`snapshot_spacing`), publishes a snapshot once per `batch_period`, as an idle batch
does: the snapshot's write is most of a step's cost.

Behind the wall clock by more than `max_behind` (a paused or overloaded machine), the loop drops the
periods it missed (`LoopStats.overruns`) rather than run them back to back without the controller's
commands; the periods that came due during an idle sleep, late by design, get one `batch_period`
more (`behind_limit`).
"""

from __future__ import annotations

import functools
import math
import os
import queue
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, Protocol, TypeVar

from app.runtime.simulated import Simulated


@dataclass
class LoopStats:
    """Timing (s) and health of the loop, published with every snapshot."""

    ticks: int = 0
    rate_hz: float = 0.0
    lateness_p50: float = 0.0
    lateness_p99: float = 0.0
    overruns: int = 0  # periods skipped because the loop fell too far behind
    batched: int = 0  # ticks stepped in an idle batch (not at 1 ms granularity)
    realtime_priority: bool = False
    step_errors: int = 0  # steps that raised (the robot was stopped, the loop went on)
    last_step_error: str = ""
    fatal: str = ""  # why the loop ended (then the process exits)


S = TypeVar("S")  # the world's snapshot type
F = TypeVar("F", bound=Callable[..., object])

_READS_WORLD = "reads_world"


def reads_world(fn: F) -> F:
    """Mark a command that only reads the world (a parameter's value, the scene's sizes): it is
    run and answered at the next tick as any command, but it does not keep the loop at 1 ms
    granularity for `fine_hold` afterwards, as a command that may set the robot going does."""
    setattr(fn, _READS_WORLD, True)
    return fn


def only_reads(fn: Callable[..., object]) -> bool:
    """Is fn (or the function a functools.partial wraps) marked by `reads_world`?"""
    while isinstance(fn, functools.partial):
        fn = fn.func
    return bool(getattr(fn, _READS_WORLD, False))


@dataclass
class Published(Generic[S]):
    """What the loop publishes after every step: the world's snapshot and the loop's figures."""

    snapshot: S
    stats: LoopStats


Reply = Callable[[int, bool, object], None]  # (call id, ok, result or exception)


class SharedSeconds(Protocol):
    """A number shared with the server's process (multiprocessing's RawValue("d")), in s."""

    value: float


class SimulationLoop(Generic[S]):
    max_behind = 0.05  # s; further behind than this (`behind_limit`), the loop drops the missed periods
    stats_every = 100  # ticks between two updates of the lateness percentiles
    batch_period = 0.05  # s between two wake-ups of an idle loop
    fine_hold = 1.0  # s at 1 ms granularity after the last command

    def __init__(
        self,
        world: Simulated[S],
        publish: Callable[[Published[S]], None],
        reply: Reply,
        realtime: bool = True,
        granularity: SharedSeconds | None = None,
        sample: Callable[[Simulated[S]], None] | None = None,
        snapshot_spacing: SharedSeconds | None = None,
    ) -> None:
        """granularity: a shared value (.value, s) the server sets to the finest spacing of steps its
        readers need now (app/runtime/process.py, `needs`); None: only `batch_period`.
        sample: called with the world after every step, published or not (every step's F_ext).
        snapshot_spacing: as granularity, for the snapshots' readers alone (`_snapshot_due`);
        None: every step at 1 ms granularity is published."""
        self._sample = sample
        self.world = world
        self._granularity = granularity
        self._snapshot_spacing = snapshot_spacing
        self._published_time = -math.inf  # s, simulation time of the last snapshot published
        self.realtime = realtime
        self._publish = publish
        self._reply = reply
        self._commands: queue.SimpleQueue[tuple[int, Callable[..., object], tuple]] = queue.SimpleQueue()
        self._lateness: deque[float] = deque(maxlen=5000)
        self.stats = LoopStats()
        self._stop = threading.Event()
        self._wake = threading.Event()  # set by a command or stop(): ends an idle sleep at once
        self._started = 0.0
        self._last_command = 0.0  # perf_counter() of the last command run
        self._catching_up = False  # stepping the periods that came due during an idle sleep
        self._slept_until = -math.inf  # perf_counter s: the end of the last idle sleep (`behind_limit`)

    def submit(self, call_id: int, fn: Callable[..., object], args: tuple) -> None:
        """Queue fn(world, *args) for the next tick; reply(call_id, ...) answers it."""
        self._commands.put((call_id, fn, args))
        self._wake.set()

    def stop(self) -> None:
        self._stop.set()
        self._wake.set()

    def wake_period(self, now: float) -> float:
        """s of wall clock between two wake-ups: one control period while somebody commands the
        robot, a command came lately or a reader needs it; otherwise an idle batch."""
        if self.world.commanded or now - self._last_command <= self.fine_hold:
            return self.world.config.dt
        needed = self._granularity.value if self._granularity is not None else self.batch_period
        return max(self.world.config.dt, min(self.batch_period, needed))

    def behind_limit(self, tick: float) -> float:
        """s behind the wall clock beyond which the loop drops the missed periods, for the period due
        at `tick` (perf_counter s): `max_behind` (a controller's commands meet the world as late as
        they were sent, never a longer backlog of steps run without them); one `batch_period` more
        for a period that came due while the loop slept idle (`_slept_until`): it is late by design,
        and a late wake-up keeps `max_behind` of room."""
        return self.max_behind + (self.batch_period if tick <= self._slept_until else 0.0)

    def run(self) -> None:
        """Tick until stopped (in the calling thread); records `fatal` if something escapes."""
        if self.realtime:
            self.stats.realtime_priority = raise_priority()
        self._started = time.perf_counter()
        try:
            self._tick_forever()
        except BaseException as exc:
            self.stats.fatal = f"{type(exc).__name__}: {exc}"
            self._publish(Published(self.world.snapshot(), self.stats))
            raise

    def _tick_forever(self) -> None:
        period = self.world.config.dt
        next_tick = time.perf_counter()
        while not self._stop.is_set():
            done, changed = self._run_commands()
            # an idle batch's catch-up publishes only its last step (no reader needs finer), and any
            # step that answers a command (its effect must be in the snapshot)
            now = time.perf_counter()
            publish = bool(done) or (now < next_tick + period if self._catching_up else self._snapshot_due(now))
            try:
                self._step(publish)
            finally:  # answered once their effect is in the snapshot (or the step failed)
                for call_id, ok, value in done:
                    self._reply(call_id, ok, value)
            if not self.realtime:
                continue
            next_tick += period
            now = time.perf_counter()
            if changed:
                self._last_command = now
            if now - next_tick > self.behind_limit(next_tick):  # far behind (paused, overloaded): resync
                self.stats.overruns += 1
                next_tick = now
            elif (wake := self.wake_period(now)) > period:  # idle: sleep until a batch is due (or a
                self._slept_until = next_tick - period + wake  # command comes), then catch up
                if next_tick > now:
                    self._wake.wait(self._slept_until - now)
                    self._wake.clear()
                self.stats.batched += 1
                self._catching_up = True
                continue
            elif next_tick > now:
                self._catching_up = False
                time.sleep(next_tick - now)
            if not self._catching_up:  # a batch's due periods are late by design, not by load
                self._lateness.append(max(0.0, time.perf_counter() - next_tick))

    def _snapshot_due(self, now: float) -> bool:
        """At 1 ms granularity, is the coming step's snapshot published? Every step while somebody
        commands the robot, a command came lately or a reader of snapshots needs one at least every
        `batch_period` (a reader looking on a schedule of its own finds a fresh one whenever it
        looks); otherwise (an idle loop kept fine only by a reader of every step's sample) once
        `batch_period` has passed, as an idle batch publishes."""
        if (
            self._snapshot_spacing is None
            or self._snapshot_spacing.value <= self.batch_period
            or self.world.commanded
            or now - self._last_command <= self.fine_hold
        ):
            return True
        dt = self.world.config.dt
        return self.world.time + dt - self._published_time >= self.batch_period - dt / 2

    def _step(self, publish: bool = True) -> None:
        stats = self.stats
        try:
            self.world.step()
        except Exception as exc:  # noqa: BLE001 - a simulation bug stops the robot, not the loop
            stats.step_errors += 1
            stats.last_step_error = f"{type(exc).__name__}: {exc}"
            self.world.fail(f"simulation error: {stats.last_step_error}")
        stats.ticks += 1
        if stats.ticks % self.stats_every == 0:
            self._update_timing()
        if self._sample is not None:
            self._sample(self.world)
        if publish:
            self._publish(Published(self.world.snapshot(), stats))
            self._published_time = self.world.time

    def _update_timing(self) -> None:
        late = sorted(self._lateness)
        if late:
            self.stats.lateness_p50 = late[len(late) // 2]
            self.stats.lateness_p99 = late[min(len(late) - 1, int(0.99 * len(late)))]
        elapsed = time.perf_counter() - self._started
        self.stats.rate_hz = self.stats.ticks / elapsed if elapsed > 0 else 0.0

    def _run_commands(self) -> tuple[list[tuple[int, bool, object]], bool]:
        """Run the queued functions: their (call id, ok, result or exception), and whether any of
        them was more than a read (`reads_world`)."""
        done: list[tuple[int, bool, object]] = []
        changed = False
        while True:
            try:
                call_id, fn, args = self._commands.get_nowait()
            except queue.Empty:
                return done, changed
            changed = changed or not only_reads(fn)
            try:
                done.append((call_id, True, fn(self.world, *args)))
            except BaseException as exc:  # noqa: BLE001 - handed back to the caller, never kills the loop
                done.append((call_id, False, exc))


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
