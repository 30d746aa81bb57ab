"""The client's message-delivery policy (rosclient/delivery.py), rule by rule: time is a fake clock
the test moves; the callback thread is the test's own, held in its callback until released; every
wait has a bound (a hung rule fails, it never asserts how long anything took)."""

from __future__ import annotations

import sys
import threading

import pytest

from rosclient import delivery
from rosclient.delivery import KEEPUP_SHARE, KEEPUP_WINDOW_S, Callbacks, Mailbox, Workload
from tests.waiting import wait_for

FOREVER = 3600.0  # a hand-off bound no test reaches: an offer that waited for it would hang the test


class Clock:
    """Time as the test sets it (s)."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def clock() -> Clock:
    return Clock()


class Taker:
    """A subscriber's callback thread: takes the mailbox's messages in turn; each callback records its
    message and, while `hold` is set, stays in the callback until released."""

    def __init__(self, mailbox: Mailbox) -> None:
        self.mailbox = mailbox
        self.handled: list = []
        self.hold = threading.Event()
        self.release = threading.Event()
        self.in_callback = threading.Event()
        self.callbacks_ended = 0
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        while (taken := self.mailbox.take()) is not None:
            item, started = taken
            self.handled.append(item)
            if self.hold.is_set():
                self.in_callback.set()
                assert self.release.wait(60)
                self.release.clear()
            self.mailbox.done(started)
            self.callbacks_ended += 1
            self.in_callback.clear()

    def idle(self) -> bool:
        return self.mailbox._taker_idle and not self.mailbox.queue

    def stop(self) -> None:
        self.release.set()
        self.mailbox.close()
        self.thread.join(30)
        assert not self.thread.is_alive()


def offered(mailbox: Mailbox, *items: object) -> None:
    """Offer `items` from a reader thread of their own: it must be done within the bound (it did
    not wait for the taker)."""
    reader = threading.Thread(target=lambda: [mailbox.offer(item) for item in items], daemon=True)
    reader.start()
    reader.join(30)
    assert not reader.is_alive(), "the reader waited for the callback"


# --- queue_size ------------------------------------------------------------------------------------


@pytest.mark.parametrize("size", [None, 0, -1])
def test_no_queue_size_is_an_unbounded_queue_that_drops_nothing(size, clock):
    mailbox: Mailbox[int] = Mailbox(size, clock, handoff_s=FOREVER)
    offered(mailbox, *range(1000))
    assert list(mailbox.queue) == list(range(1000)) and mailbox.received == 1000


def test_a_full_queue_drops_its_oldest():
    queue = delivery.bounded_queue(3)
    queue.extend(range(5))
    assert list(queue) == [2, 3, 4]
    assert delivery.bounded_queue(0).maxlen is None and delivery.bounded_queue(None).maxlen is None


def test_the_lab_holds_queue_size_messages_for_a_rospy_subscriber_else_every_message():
    assert delivery.lab_queue_length(1) == 1
    assert delivery.lab_queue_length(10) == 10
    assert delivery.lab_queue_length(None) == delivery.LAB_QUEUE == 0
    assert delivery.lab_queue_length(0) == delivery.LAB_QUEUE
    assert delivery.lab_queue_length(-5) == delivery.LAB_QUEUE


# --- newest wins when the callback does not keep up ------------------------------------------------


def test_before_its_first_callback_a_subscriber_is_not_waited_for_the_newest_wins(clock):
    mailbox: Mailbox[int] = Mailbox(1, clock, handoff_s=FOREVER)  # no callback thread at all
    offered(mailbox, 1, 2, 3)
    assert list(mailbox.queue) == [3] and mailbox.received == 3


def test_a_callback_busy_beyond_the_share_is_not_waited_for_and_gets_the_newest(clock):
    mailbox: Mailbox[int] = Mailbox(1, clock, handoff_s=FOREVER)
    taker = Taker(mailbox)
    try:
        taker.hold.set()
        offered(mailbox, 1)
        wait_for(taker.in_callback.is_set)  # busy from now on, since its first callback's start
        clock.now += 0.5  # at work all of the 0.5 s since: more than KEEPUP_SHARE of it
        offered(mailbox, 2, 3, 4)  # the queue full at 3: each dropped the oldest without waiting
        assert list(mailbox.queue) == [4]
        taker.hold.clear()
        taker.release.set()
        wait_for(lambda: taker.handled == [1, 4])
    finally:
        taker.stop()


# --- the hand-off wait when the callback keeps up ---------------------------------------------------


def test_a_callback_that_keeps_up_gets_a_burst_in_order(clock):
    mailbox: Mailbox[int] = Mailbox(1, clock, handoff_s=FOREVER)
    taker = Taker(mailbox)
    try:
        wait_for(taker.idle)  # waiting for a message: waited for, though it never ran a callback
        mailbox.offer(0)
        mailbox.offer(1)  # the queue full unless 0 was taken: the reader waited for the take
        wait_for(lambda: taker.handled == [0, 1])
        clock.now += KEEPUP_WINDOW_S  # its callbacks take no time on this clock: it keeps up
        for k in range(2, 200):  # back to back: each waits for the taker to take the one before
            mailbox.offer(k)
        wait_for(lambda: len(taker.handled) == 200)
        assert taker.handled == list(range(200))
    finally:
        taker.stop()


def run_callbacks(taker: Taker, clock: Clock, mailbox: Mailbox, busy_s: float, idle_s: float, count: int) -> None:
    """`count` callbacks, each `busy_s` at work (held while the clock moves) then `idle_s` waiting."""
    taker.hold.set()
    for k in range(count):
        wait_for(taker.idle)
        mailbox.offer(-1 - k)
        wait_for(taker.in_callback.is_set)
        clock.now += busy_s
        ended = taker.callbacks_ended
        taker.release.set()
        wait_for(lambda ended=ended: taker.callbacks_ended > ended)
        clock.now += idle_s
    wait_for(taker.idle)


def test_a_callback_that_keeps_up_is_waited_for_while_it_runs_so_it_gets_the_queued_message(clock):
    mailbox: Mailbox[int] = Mailbox(1, clock, handoff_s=FOREVER)
    taker = Taker(mailbox)
    try:
        run_callbacks(taker, clock, mailbox, busy_s=0.1, idle_s=0.4, count=2)  # at work 20 % of the time
        offered(mailbox, 1)
        wait_for(taker.in_callback.is_set)  # running on 1
        clock.now += 0.1
        offered(mailbox, 2)  # queued: the queue has room
        reader = threading.Thread(target=mailbox.offer, args=(3,), daemon=True)
        reader.start()  # queue full, the callback keeps up: the reader waits for it to take 2
        wait_for(lambda: mailbox.handing_off)
        assert list(mailbox.queue) == [2]
        taker.hold.clear()
        taker.release.set()
        reader.join(30)
        assert not reader.is_alive()
        wait_for(lambda: taker.handled[2:] == [1, 2, 3])  # nothing lost
    finally:
        taker.stop()


def test_the_wait_is_bounded_then_the_late_taker_is_not_waited_for_until_it_takes_one(clock):
    mailbox: Mailbox[int] = Mailbox(1, clock, handoff_s=0.0)  # any wait runs out at once
    taker = Taker(mailbox)
    try:
        run_callbacks(taker, clock, mailbox, busy_s=0.1, idle_s=0.4, count=2)
        offered(mailbox, 1)
        wait_for(taker.in_callback.is_set)
        clock.now += 0.1  # running, and keeping up
        offered(mailbox, 2, 3)  # 3's wait for the taker ran out: 2 dropped
        assert list(mailbox.queue) == [3] and mailbox._taker_late
        mailbox.handoff_s = FOREVER  # were it waited for again, the reader would hang here
        offered(mailbox, 4)
        assert list(mailbox.queue) == [4]
        taker.hold.clear()
        taker.release.set()
        wait_for(lambda: taker.handled[2:] == [1, 4])  # it takes one: waited for again from now
        assert not mailbox._taker_late
    finally:
        taker.stop()


# --- keeping up: the share of the window at work ----------------------------------------------------


def test_a_callback_keeps_up_while_at_work_less_than_the_share_of_the_window(clock):
    work = Workload(clock)
    assert not work.keeps_up()  # before its first callback
    started = work.started()
    clock.now += 0.3
    work.ended(started)
    clock.now += 0.1  # at work 0.3 of 0.4 s since its first callback: 75 %
    assert work.keeps_up()
    started = work.started()
    clock.now += 0.65  # 0.95 of the last 1.0 s, the running one counted: over KEEPUP_SHARE
    assert KEEPUP_SHARE * KEEPUP_WINDOW_S <= 0.95 and not work.keeps_up()
    work.ended(started)
    clock.now += 0.5  # the first ended before the last 1.0 s: 0.65 of it at work
    assert work.keeps_up()


def test_callbacks_ended_before_the_window_are_forgotten(clock):
    work = Workload(clock)
    started = work.started()
    clock.now += 0.95
    work.ended(started)  # at work 0.95 s: it did not keep up
    clock.now += 0.5
    started = work.started()
    clock.now += 0.05  # the long callback ended 0.55 s ago, inside the window: 1.0 s at work
    assert not work.keeps_up()
    work.ended(started)
    clock.now += KEEPUP_WINDOW_S - 0.5  # it ended more than the window ago: only the 0.05 s one counts
    started = work.started()
    clock.now += 0.05
    assert work.keeps_up()


# --- the reader's turns, the callbacks at the program's end -----------------------------------------


def test_the_interpreter_passes_between_threads_every_reader_switch_s_or_sooner():
    before = sys.getswitchinterval()
    try:
        sys.setswitchinterval(0.005)  # Python's default
        delivery.reader_turns()
        assert sys.getswitchinterval() == pytest.approx(delivery.READER_SWITCH_S)
        sys.setswitchinterval(delivery.READER_SWITCH_S / 2)  # already sooner: kept
        delivery.reader_turns()
        assert sys.getswitchinterval() == pytest.approx(delivery.READER_SWITCH_S / 2)
    finally:
        sys.setswitchinterval(before)


def test_a_closed_mailbox_hands_nothing_more_to_its_taker(clock):
    mailbox: Mailbox[int] = Mailbox(5, clock)
    mailbox.offer(1)
    mailbox.close()
    assert mailbox.take() is None


def test_the_programs_end_waits_for_a_running_callback_until_it_ends():
    callbacks = Callbacks()
    release, waited = threading.Event(), []

    def callback() -> None:
        with callbacks:
            assert release.wait(60)

    thread = threading.Thread(target=callback, daemon=True)
    thread.start()
    wait_for(lambda: callbacks.running() == 1)
    assert not callbacks.wait(timeout=0.0)  # still running: the grace not over, the wait goes on
    ender = threading.Thread(target=lambda: waited.append(callbacks.wait(timeout=60)), daemon=True)
    ender.start()
    release.set()
    ender.join(30)
    thread.join(30)
    assert waited == [True] and callbacks.running() == 0
