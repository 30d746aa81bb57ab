"""bench/rospy_floor.py, the reference for issue 31's F_ext figure: rospy's receive rule as ros_comm
has it (msg.py's deserialize_messages: the newest queue_size complete messages of a read, an
incomplete one kept for the next read) and the callback's tally of what it saw."""

import struct

from bench.fext_callback import Tally
from bench.rospy_floor import frame, receive_once


def _ticks(frames: list[bytes]) -> list[int]:
    return [struct.unpack_from("<I", f)[0] for f in frames]


def test_a_read_of_three_messages_and_a_half_keeps_the_newest_queue_size():
    read = frame(0) + frame(1) + frame(2) + frame(3)[:10]
    kept, rest = receive_once(read, 1)
    assert _ticks(kept) == [2] and rest == frame(3)[:10]
    kept, rest = receive_once(read, 2)
    assert _ticks(kept) == [1, 2]
    kept, rest = receive_once(rest + frame(3)[10:], 1)  # the next read completes the fourth
    assert _ticks(kept) == [3] and rest == b""


def test_the_tally_counts_the_samples_over_the_span_it_saw_and_the_slow_callbacks():
    tally = Tally()
    for stamp_ms in (0, 1, 4):  # 2 and 3 dropped
        tally.handle(stamp_ms * 1_000_000)
    figures = tally.figures()
    assert figures["published"] == 5 and figures["handled"] == 3
    assert 0 <= figures["slow"] <= 3 and all(d >= 0.0002 for d in tally.durations_s)


def test_how_far_behind_the_freshest_is_read_off_the_lateness_of_each_message():
    tally = Tally(work_s=0.0)
    tally.lateness_s = [0.010, 0.012, 0.050, 0.011]  # the wall clock minus the stamp, an offset apart
    assert tally.behind_ms(0.0) == 0.0
    assert abs(tally.behind_ms(0.5) - 1.0) < 1e-9  # the second of 10, 11, 12, 50 ms
    assert abs(tally.behind_ms(1.0) - 40.0) < 1e-9
