"""An idle lab sleeps (app/runtime/loop.py): with nobody commanding the robot the real-time loop
steps in batches; the steps are the same ones (the same world at the same tick as stepping it
directly), and a command brings 1 ms granularity back until the robot is left alone again."""

import itertools
import threading
import time
from functools import partial

import numpy as np

from sim.world import World

from app.lab import commands as cmd
from app.runtime.loop import SimulationLoop
from tests.waiting import wait_for


class _Running:
    """A real-time SimulationLoop in a thread; keeps the first snapshot published at or after
    `keep_tick` ticks, with its tick count."""

    def __init__(self, world: World, keep_tick: int = -1) -> None:
        self.replies: dict[int, tuple[bool, object]] = {}
        self.kept = None
        self.keep_tick = keep_tick
        self.loop = SimulationLoop(world, self._publish, self._reply, realtime=True)
        self.thread = threading.Thread(target=self.loop.run, daemon=True)

    def _publish(self, published) -> None:
        if self.kept is None and self.keep_tick >= 0 and published.stats.ticks >= self.keep_tick:
            self.kept = (published.stats.ticks, published.snapshot)  # a batch publishes only its last step

    def _reply(self, call_id: int, ok: bool, value) -> None:
        self.replies[call_id] = (ok, value)

    def call(self, call_id: int, fn, *args):
        self.loop.submit(call_id, fn, args)
        ok, value = wait_for(lambda: self.replies.get(call_id))
        assert ok, value
        return value

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self.loop.stop()
        self.thread.join(timeout=30)
        assert not self.thread.is_alive()


def test_an_idle_loop_steps_in_batches_the_same_steps():
    ticks = 300
    with _Running(World(), keep_tick=ticks) as running:
        wait_for(lambda: running.kept is not None)
        assert running.loop.stats.batched > 0  # nobody commands the robot: it slept between batches
    stepped, kept = running.kept
    reference = World()
    for _ in range(stepped):
        reference.step()
    assert kept.time == reference.time
    assert np.array_equal(kept.q, reference.arm.q)
    assert np.array_equal(kept.box_position, reference.box.position)
    assert np.array_equal(kept.palm_position, reference.human.position)
    assert np.array_equal(kept.wrench_ee, reference.wrench_ee)


def test_a_commanded_robot_is_stepped_at_1_ms_granularity_and_idles_again_when_left_alone():
    world = World()
    with _Running(world) as running:
        loop = running.loop
        loop.fine_hold = 0.05  # s: keep the test short; the rule is the same
        wait_for(lambda: loop.stats.batched > 0)
        running.call(1, cmd.start_lifting, 10.0)
        assert world.commanded
        batched, ticks = loop.stats.batched, loop.stats.ticks
        wait_for(lambda: loop.stats.ticks >= ticks + 300)
        assert loop.stats.batched == batched  # lifting runs: no tick was batched
        running.call(2, cmd.stop_lifting)
        wait_for(lambda: not world.commanded)  # the command ramps down to zero (rate limit)
        wait_for(lambda: loop.stats.batched > batched)  # left alone: it sleeps again


def test_reading_the_world_leaves_an_idle_loop_idle():
    """A page reads a parameter every second or two (static/app.js): a command marked `reads_world`
    is answered at the next tick, and the loop goes on sleeping between batches (before, every read
    held it at 1 ms granularity for `fine_hold` and an idle lab with a page open spent ~2.5 times
    its CPU: docs/performance.md)."""
    world = World()
    with _Running(world) as running:
        loop = running.loop
        wait_for(lambda: loop.stats.batched > 0)
        ids = itertools.count(1)
        batched = loop.stats.batched

        def read_and_look() -> bool:
            assert running.call(next(ids), partial(cmd.get_lifting, field="mu")) == world.params.mu
            assert running.call(next(ids), cmd.controller_choice) == "sp"
            return loop.stats.batched > batched + 3  # idle batches between the reads

        wait_for(read_and_look)


def test_a_commanded_loop_stalled_beyond_max_behind_drops_the_periods_it_missed():
    """At 1 ms granularity the loop runs at most `max_behind` of missed periods back to back: a
    controller's commands never meet a longer backlog of steps run without them (an idle batch's
    periods, late by design, get one `batch_period` more: `behind_limit`)."""
    world = World()
    with _Running(world) as running:
        loop = running.loop
        running.call(1, cmd.start_lifting, 10.0)
        ticks = loop.stats.ticks
        wait_for(lambda: loop.stats.ticks >= ticks + 3 * loop.batch_period / world.config.dt)  # past the idle periods
        overruns = loop.stats.overruns
        running.call(2, lambda w: time.sleep(1.5 * loop.max_behind))  # a stall in the loop (a paused machine)
        wait_for(lambda: loop.stats.overruns > overruns)


def test_readers_set_how_often_an_idle_loop_wakes():
    from app.runtime.process import SimulationProcess

    world = World()
    process = SimulationProcess(world)  # not started: only its registry of needs is used here
    loop = SimulationLoop(world, lambda published: None, lambda *answer: None, granularity=process._granularity)
    now = loop.fine_hold + 1.0  # s after the (never) last command
    assert loop.wake_period(now) == loop.batch_period
    with process.needs(0.01):  # a 100 Hz topic stream
        assert loop.wake_period(now) == 0.01
        with process.needs(0.005):  # and a recording
            assert loop.wake_period(now) == 0.005
            with process.needs(0.0002):  # faster than the control period: every tick
                assert loop.wake_period(now) == world.config.dt
        assert loop.wake_period(now) == 0.01
    assert loop.wake_period(now) == loop.batch_period
    assert loop.wake_period(loop.fine_hold / 2) == world.config.dt  # a command came lately


def test_an_idle_loop_kept_fine_for_every_step_s_sample_publishes_as_the_snapshots_readers_need():
    """A 1 kHz F_ext reader keeps the loop at 1 ms steps (each step sampled), not publishing each
    snapshot: an idle batch's spacing does; with a reader of snapshots every 10 ms, every step's is
    published, so a look on its own schedule always finds a fresh one."""
    from app.runtime.process import SimulationProcess

    world = World()
    process = SimulationProcess(world)  # not started: only its registry of needs is used here
    published: list[float] = []
    sampled: list[float] = []
    loop = SimulationLoop(
        world,
        lambda p: published.append(p.snapshot.time),
        lambda *answer: None,
        granularity=process._granularity,
        snapshot_spacing=process._snapshot_spacing,
        sample=lambda stepped: sampled.append(stepped.time),
    )
    dt = world.config.dt
    thread = threading.Thread(target=loop.run, daemon=True)
    thread.start()
    try:
        with process.needs(0.001, snapshots=False):
            ticks = loop.stats.ticks
            wait_for(lambda: loop.stats.ticks >= ticks + 3 * loop.batch_period / dt)  # the last batch is over
            first, ticks = len(published), loop.stats.ticks
            wait_for(lambda: loop.stats.ticks >= ticks + 8 * loop.batch_period / dt)  # 5 spacings or more
            spaced = np.diff(published[first:])
            assert len(spaced) >= 5 and spaced.min() >= loop.batch_period - dt / 2
            with process.needs(0.01):
                wait_for(lambda: len(published) > first + len(spaced) + 3)
                first = len(published)
                wait_for(lambda: len(published) >= first + 100)
                assert np.allclose(np.diff(published[first : first + 100]), dt)  # every step's
        assert np.allclose(np.diff(sampled), dt)  # every step sampled, whatever was published
    finally:
        loop.stop()
        thread.join(timeout=30)
    assert not thread.is_alive()
