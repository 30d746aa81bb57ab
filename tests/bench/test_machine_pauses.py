"""bench/machine_pauses.py's reading of its timings: slow computations close together are one
window, with its length and its worst slow-down."""

from bench.machine_pauses import windows


def test_slow_computations_close_together_are_one_window():
    median = 0.001
    timings = [
        (0.0, 0.001),
        (1.000, 0.010),  # 10 times: a window opens
        (1.050, 0.015),  # 15 times, 50 ms later: the same window
        (1.100, 0.001),
        (2.500, 0.005),  # 5 times, far from the first: a second window
        (3.000, 0.003),  # 3 times: not slow
    ]
    found = windows(median, timings)
    assert [(round(a, 3), round(b, 3), round(c, 1)) for a, b, c in found] == [(1.0, 1.065, 15.0), (2.5, 2.505, 5.0)]
